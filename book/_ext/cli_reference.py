"""The parser the CLI reference page renders: the command's own, without the epilogs.

Each command's ``--help`` ends with the same notes on output and exit statuses,
laid out for a terminal; the reference page states them once, above the
generated part, so the parser it renders (``:func: reference_parser``) leaves
them out. Everything else (commands, arguments, options, their help) is the
installed command's parser, unchanged.
"""

import argparse

from clap_unified.cli import build_parser


def reference_parser() -> argparse.ArgumentParser:
    """:func:`clap_unified.cli.build_parser` with every parser's epilog removed."""
    parser = build_parser()
    stack = [parser]
    while stack:
        p = stack.pop()
        p.epilog = None
        for action in p._actions:
            if isinstance(action, argparse._SubParsersAction):
                stack.extend(action.choices.values())
    return parser


def setup(app):
    """Nothing to register: the module is imported by the ``argparse`` directive."""
    return {"parallel_read_safe": True, "parallel_write_safe": True}
