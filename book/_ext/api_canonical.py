"""The API reference: every public object of ``clap_unified`` described once, and found.

The reference pages run ``automodule`` on each subpackage (its ``__all__``) and on each of
its modules. An object re-exported by a package (``clap_unified.spaces.LineSpace``, defined
in ``clap_unified.spaces.lines``) would then be described twice; ``skip_member`` keeps the
description at the deepest package that exports it (constants stay in their own module,
where autodoc finds their ``#:`` comment) and skips it everywhere else.

``resolve_canonical`` then resolves a reference written with an object's defining path, or
with its short name inside a docstring, to that one description; a method named on a class
that inherits it resolves to the class that defines it. What stays unresolved is a warning
of the nitpicky build, fixed in the docstring.

Two small adaptations: numpydoc sections of a *module* docstring (``Examples`` over dashes)
become rubrics, since as reST section titles they clash with the page's headings; and
``nitpick_ignore`` entries, lists when they come from ``_config.yml``, become the tuples
Sphinx looks up.
"""

from __future__ import annotations

import importlib
import inspect
import re
import sys

PACKAGE = "clap_unified"


def _defining_module(name: str, obj) -> str | None:
    """The module that defines ``name``: ``__module__`` for functions and classes, the
    module whose source assigns it at top level for constants."""
    owner = getattr(obj, "__module__", None)
    if isinstance(owner, str) and (inspect.isclass(obj) or inspect.isroutine(obj)):
        return owner
    pattern = re.compile(rf"^{re.escape(name)}\s*(:[^=\n]*)?=", re.MULTILINE)
    for mod_name, mod in sorted(sys.modules.items()):
        if not mod_name.startswith(PACKAGE) or getattr(mod, name, None) is not obj:
            continue
        try:
            source = inspect.getsource(mod)
        except (OSError, TypeError):
            continue
        if pattern.search(source):
            return mod_name
    return None


def canonical_module(module_name: str, name: str, obj) -> str | None:
    """Where ``name`` is documented: the deepest package that is a prefix of its defining
    module and lists it in ``__all__``; else the defining module."""
    origin = _defining_module(name, obj)
    if origin is None or not origin.startswith(PACKAGE):
        return None
    if not (inspect.isclass(obj) or inspect.isroutine(obj)):
        return origin  # a constant: autodoc reads its ``#:`` comment in its own module
    parts = origin.split(".")
    for k in range(len(parts) - 1, 0, -1):
        package = ".".join(parts[:k])
        mod = importlib.import_module(package)
        if name in getattr(mod, "__all__", ()) and getattr(mod, name, None) is obj:
            return package
    return origin


def skip_member(app, what, name, obj, skip, options):
    """Skip a module's member that is documented elsewhere."""
    if what != "module":
        return None
    if inspect.ismodule(obj):  # a subpackage in __all__ has its own section
        return True
    current = app.env.temp_data.get("autodoc:module")
    if current is None:
        return None
    home = canonical_module(current, name, obj)
    if home is not None and home != current:
        return True
    return None


_SECTION = re.compile(r"^([A-Z][A-Za-z ]+)\n-{3,}$")


def module_sections_as_rubrics(app, what, name, obj, options, lines):
    """A module docstring's numpydoc sections (``Examples`` over dashes) as rubrics: as
    reST section titles they would clash with the page's own headings."""
    if what != "module":
        return
    k = 0
    while k < len(lines) - 1:
        if _SECTION.match(f"{lines[k]}\n{lines[k + 1]}"):
            lines[k:k + 2] = [f".. rubric:: {lines[k]}", ""]
        k += 1


def _locate(dotted: str):
    """The object at a dotted path (module prefix imported, the rest looked up), and the
    path of its module-level owner, or (None, None)."""
    parts = dotted.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        owner = ".".join(parts[:k])
        rest = parts[k:]
        for depth, attr in enumerate(rest):
            if not hasattr(obj, attr):
                return None, None
            if depth == 0:
                owner_name, owner_obj = attr, getattr(obj, attr)
            obj = getattr(obj, attr)
        if not rest:
            return None, None  # a module: documented under its own name
        return (owner, owner_name, owner_obj), rest[1:]
    return None, None


def resolve_canonical(app, env, node, contnode):
    """Resolve a Python reference written with an object's defining path
    (``clap_unified.maps.field.field_landmarks``) or, inside a docstring, its short name
    (``field_landmarks``), to where the object is documented (``clap_unified.maps``)."""
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip(".~")
    module = node.get("py:module")
    cls = node.get("py:class")
    candidates = [target]
    if module:
        candidates = ([f"{module}.{cls}.{target}"] if cls else []) + [f"{module}.{target}",
                                                                     target]
    domain = env.get_domain("py")
    for dotted in candidates:
        if not dotted.startswith(PACKAGE):
            continue
        found, rest = _locate(dotted)
        if found is None:
            continue
        owner, name, obj = found
        if rest and inspect.isclass(obj):  # a member: documented on the class defining it
            definer = next((k for k in obj.__mro__ if rest[0] in vars(k)), obj)
            if definer is not obj and definer.__module__.startswith(PACKAGE):
                owner, name, obj = definer.__module__, definer.__name__, definer
        home = canonical_module(owner, name, obj)
        if home is None:
            continue
        new = ".".join([home, name, *rest])
        if new == node["reftarget"]:
            continue
        resolved = domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], new,
                                       node, contnode)
        if resolved is not None:
            return resolved
    return None


def _ignore_as_tuples(app, config):
    """``nitpick_ignore`` from YAML is a list of lists; Sphinx looks tuples up in it."""
    config.nitpick_ignore = [tuple(entry) for entry in config.nitpick_ignore]


def setup(app):
    app.connect("config-inited", _ignore_as_tuples)
    app.connect("autodoc-skip-member", skip_member)
    app.connect("autodoc-process-docstring", module_sections_as_rubrics)
    app.connect("missing-reference", resolve_canonical)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
