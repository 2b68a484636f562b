"""Running the experiments (one process, joblib or Dask) and writing the results.

Every file is written atomically (a temporary file in the same folder, then
a rename), so an interrupted run leaves no half-written file; a finished
experiment is cached in ``DIR/experiments/<name>.json`` and reused by the
next run with the same parameters and the same code (``code_fingerprint``)
unless ``force`` is given.

Layout of ``DIR``::

    claims.json  claims.md  timings.json
    experiments/<name>.json        cached outputs
    tables/<experiment>_<table>.csv
    figures/<figure>.png, .svg
"""

from __future__ import annotations

import csv
import functools
import io
import json
import os
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import progress as _progress
from .claims import (
    _differs,
    alternatives_count,
    alternatives_text,
    claim_block,
    describe_variant,
    evaluate_claims,
    keep_units,
)
from .data import missing_datasets
from .registry import EXPERIMENTS, finite_or_none, seed_for

__all__ = ["MissingDataError", "Reproduction", "claims_markdown", "reproduce", "run_experiment",
           "verdicts_markdown", "write_atomic"]

#: Bump when the cache format changes.
CACHE_FORMAT = 1


class MissingDataError(OSError):
    """A data set needed by an experiment is missing (the message says where to put it)."""


@dataclass
class Reproduction:
    """What :func:`reproduce` did.

    Attributes
    ----------
    out : Path
    claims : list of dict
        As written to ``claims.json``.
    ran, reused : list of str
        Experiments computed in this run, and those taken from the cache.
    skipped : dict
        Experiment -> why it was not run (missing data, with ``allow_missing``).
    seconds : float
        Wall time of the whole run.
    """

    out: Path
    claims: list
    ran: list = field(default_factory=list)
    reused: list = field(default_factory=list)
    skipped: dict = field(default_factory=dict)
    seconds: float = 0.0


def write_atomic(path, data) -> None:
    """Write ``data`` (str or bytes) to ``path`` through a temporary file and a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part")
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.fchmod(fd, 0o666 & ~umask)  # as open() would, not mkstemp's owner-only 0600
        with os.fdopen(fd, "wb") as f:
            f.write(data.encode() if isinstance(data, str) else data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def run_experiment(name: str, quick: bool, position: int = 0, show_bars: bool = True) -> dict:
    """Run one experiment with the seed of its name; ``{"name", "output", "seconds"}``."""
    _progress.configure(position, show_bars)
    ex = EXPERIMENTS[name]
    t0 = time.perf_counter()
    output = _json_data(ex.run(ex.params(quick), seed_for(name)))
    return {"name": name, "output": output, "seconds": time.perf_counter() - t0,
            "code": code_fingerprint()}


def _json_data(obj):
    """``obj`` as JSON data, non-finite floats as None: the same whether fresh or cached."""
    def clean(x):
        if isinstance(x, dict):
            return {str(k): clean(v) for k, v in x.items()}
        if isinstance(x, list | tuple):
            return [clean(v) for v in x]
        if isinstance(x, float | np.floating):
            return finite_or_none(x)
        if isinstance(x, np.integer | np.bool_):
            return x.item()
        return x

    # keys sorted as the cache stores them: a fresh output and a cached one read alike
    return json.loads(json.dumps(clean(obj), allow_nan=False, sort_keys=True))


@functools.cache
def code_fingerprint() -> str:
    """sha256 of the package's source and its package data (field maps, dataset manifests): a
    change recomputes the cache."""
    import hashlib

    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    files = sorted(root.rglob("*.py")) + sorted(root.rglob("*.json"))
    for f in files:
        h.update(f.relative_to(root.parent).as_posix().encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:16]


def _cache_key(name: str, quick: bool) -> dict:
    ex = EXPERIMENTS[name]
    return {"name": name, "mode": "quick" if quick else "full", "params": ex.params(quick),
            "version": ex.version, "format": CACHE_FORMAT, "code": code_fingerprint()}


def _dumps(obj) -> str:
    return json.dumps(obj, indent=1, sort_keys=True, allow_nan=False) + "\n"


def _load_cached(path: Path, key: dict):
    try:
        doc = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not (isinstance(doc, dict) and doc.get("key") == key):
        return None
    out = doc.get("output")
    ok = isinstance(out, dict) and isinstance(out.get("data"), str) and \
        isinstance(out.get("numbers"), dict) and isinstance(out.get("tables", {}), dict)
    return out if ok else None


def _check_out(out) -> Path:
    out = Path(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(dir=out, prefix=".probe")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OSError(f"--out {out}: not a writable folder ({exc.strerror or exc})") from None
    return out


def _client(address: str, timeout: float = 5.0):
    """A Dask client of the scheduler at ``address``, or an ``OSError`` within ``timeout`` s.

    The address must be ``[tcp://]host:port``; the port is tried first (a
    refused or silent port fails fast), then the client connects in a worker
    thread with a hard deadline, so a listener that is not a Dask scheduler
    cannot hang the command.
    """
    import socket
    import threading
    from urllib.parse import urlsplit

    def fail(why):
        return OSError(f"--scheduler {address}: {why}")

    parts = urlsplit(address if "://" in address else f"tcp://{address}")
    try:
        host, port = parts.hostname, parts.port
    except ValueError:
        host = port = None
    if parts.scheme not in ("tcp", "tls") or not host or not port:
        raise fail("expected an address like tcp://host:8786") from None
    try:
        socket.create_connection((host, port), timeout=timeout).close()
    except OSError as exc:
        raise fail(f"nothing answers there ({exc.strerror or exc})") from None

    result = {}

    def connect():  # in a daemon thread: a connection that hangs cannot keep the process alive
        try:
            from distributed import Client

            result["client"] = Client(address, timeout=f"{timeout}s", set_as_default=False)
        except Exception as exc:  # a listener that is not a Dask scheduler: any error
            result["error"] = exc

    worker = threading.Thread(target=connect, daemon=True)
    worker.start()
    worker.join(2 * timeout)
    if "client" in result:
        return result["client"]
    if "error" in result:
        exc = result["error"]
        raise fail(f"not a Dask scheduler ({type(exc).__name__}: {exc})")
    raise fail(f"no Dask scheduler answered within {2 * timeout:g} s")


def _execute(todo, quick, jobs, scheduler, bars):
    """Yield results of ``todo`` as they finish."""
    if scheduler is not None:
        from distributed import wait

        client = _client(scheduler) if isinstance(scheduler, str) else scheduler
        try:
            futures = [client.submit(run_experiment, n, quick, 0, False, pure=False,
                                     key=f"clap-unified-{n}-{time.time_ns()}") for n in todo]
            pending = set(futures)
            with client.as_current():
                while pending:
                    done, pending = wait(pending, return_when="FIRST_COMPLETED")
                    for fut in done:
                        yield fut.result()
        finally:
            if isinstance(scheduler, str):
                client.close()
    elif jobs == 1 or len(todo) == 1:
        for n in todo:
            yield run_experiment(n, quick, 1, bars)
    else:
        from joblib import Parallel, delayed

        par = Parallel(n_jobs=jobs, backend="loky", return_as="generator_unordered")
        with warnings.catch_warnings():
            # loky replaces a worker that grew in memory and says so; results are unaffected
            warnings.filterwarnings("ignore", message="A worker stopped while some jobs",
                                    category=UserWarning)
            yield from par(delayed(run_experiment)(n, quick, i + 1, bars)
                           for i, n in enumerate(todo))


def reproduce(out, *, quick: bool = False, jobs: int = 1, scheduler=None, force: bool = False,
              allow_missing: bool = False, only=None, progress: bool = True,
              log=None) -> Reproduction:
    """Run the paper's experiments and write claims, tables and figures into ``out``.

    Parameters
    ----------
    out : path
        Output folder (created).
    quick : bool
        Fewer trials, the same verdict rules.
    jobs : int
        Experiments run in parallel with joblib (loky processes).
    scheduler : str or distributed.Client, optional
        Address of a Dask scheduler (or a client): experiments run there.
    force : bool
        Recompute experiments found in the cache.
    allow_missing : bool
        Skip experiments whose data set is missing; their claims become
        ``"data unavailable"``. Without it a missing data set raises.
    only : list of str, optional
        Run these experiments only (claims of the others: "data unavailable").
    progress : bool
        tqdm bars (overall and per experiment) on standard error.
    log : callable, optional
        ``log(str)`` for the expected and the measured time (default: stderr).

    Raises
    ------
    ValueError
        ``jobs`` below 1 or an unknown experiment in ``only``.
    OSError
        ``out`` not writable, the scheduler unreachable, or a data set missing
        (:class:`MissingDataError`) without ``allow_missing``.
    """
    from tqdm.auto import tqdm

    t0 = time.perf_counter()
    log = log or (lambda s: print(s, file=sys.stderr))
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ValueError(f"--jobs: expected a whole number of at least 1, got {jobs!r}")
    names = list(EXPERIMENTS) if only is None else list(only)
    unknown = [n for n in names if n not in EXPERIMENTS]
    if unknown:
        raise ValueError(f"--only: unknown experiment(s) {unknown}; expected some of "
                         f"{list(EXPERIMENTS)}")
    out = _check_out(out)
    client = _client(scheduler) if isinstance(scheduler, str) else scheduler
    try:
        missing = missing_datasets(d for n in names for d in EXPERIMENTS[n].datasets)
        skipped = {}
        for n in names:
            why = [missing[d] for d in EXPERIMENTS[n].datasets if d in missing]
            if why:
                skipped[n] = why[0]
        needed = [n for n in skipped if not EXPERIMENTS[n].optional]
        if needed and not allow_missing:
            first = skipped[needed[0]]
            raise MissingDataError(f"{first} (or pass --allow-missing to mark the dependent "
                                   f"claims 'data unavailable')")
        outputs, result = {}, Reproduction(out, [], skipped=skipped)
        todo = []
        if only is not None:  # the other experiments' results come from the cache, if any
            for n in EXPERIMENTS:
                cached = None if n in names else _load_cached(
                    out / "experiments" / f"{n}.json", _cache_key(n, quick))
                if cached is not None:
                    outputs[n] = cached
                    result.reused.append(n)
        for n in names:
            if n in skipped:
                continue
            key = _cache_key(n, quick)
            cached = None if force else _load_cached(out / "experiments" / f"{n}.json", key)
            if cached is not None:
                outputs[n] = cached
                result.reused.append(n)
            else:
                todo.append(n)
        width = 1 if scheduler is not None else max(1, min(jobs, len(todo)))
        expected = sum(EXPERIMENTS[n].expected_seconds[0 if quick else 1] for n in todo)
        if todo:
            log(f"reproduce: {len(todo)} experiment(s) to run, about {expected / width:.0f} s "
                f"of computing expected ({'quick' if quick else 'full'} mode)")
        timings = {}
        bar = tqdm(total=len(todo), desc="reproduce", position=0, disable=None if progress
                   else True, dynamic_ncols=True)
        with bar:
            for res in _execute(todo, quick, jobs, client, progress):
                n = res["name"]
                if res["code"] != code_fingerprint():
                    raise OSError(f"--scheduler: the workers run other code than this "
                                  f"command (fingerprint {res['code']}, here "
                                  f"{code_fingerprint()}); install the same clap_unified")
                outputs[n] = res["output"]
                timings[n] = res["seconds"]
                write_atomic(out / "experiments" / f"{n}.json",
                             _dumps({"key": _cache_key(n, quick), "output": res["output"]}))
                result.ran.append(n)
                bar.update(1)
    finally:
        if isinstance(scheduler, str):
            client.close()
    # the claims name what is missing; the full message (local paths) is in ``result.skipped``
    result.claims = _json_data(evaluate_claims(outputs, {
        n: _not_here(n, missing) for n in skipped}))
    _write_report(out, outputs, result.claims, quick)
    result.seconds = time.perf_counter() - t0
    write_atomic(out / "timings.json", _dumps({"experiments": timings,
                                               "total_seconds": result.seconds}))
    log(f"reproduce: finished in {result.seconds:.0f} s ({len(result.ran)} run, "
        f"{len(result.reused)} reused, {len(result.skipped)} skipped)")
    return result


#: Why a data set's experiment did not run, in words (the claims' data lines say it).
_NOT_HERE = {
    "vpg": "the VPG images are not public",
    "homography": "the homogr and EVD image pairs are not on this machine",
    "stitching_sets": "the real panorama sets are not on this machine",
    "adelaidermf": "the AdelaideRMF sequences are not on this machine",
}


def _not_here(name: str, missing: dict) -> str:
    """Why the experiment ``name`` did not run, in words: its missing data sets (and, for an
    optional one, that its substitute stands in)."""
    why = "; ".join(_NOT_HERE.get(d, f"the data set {d} is not on this machine")
                    for d in EXPERIMENTS[name].datasets if d in missing)
    return why + ("; the substitute stands in for it" if EXPERIMENTS[name].optional else "")


# -------------------------------------------------------------------- report
def _csv(rows) -> str:
    buf = io.StringIO()
    cols = list(dict.fromkeys(k for r in rows for k in r))
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in cols})
    return buf.getvalue()


def _cell(s) -> str:
    return keep_units(str(s).replace("|", "\\|").replace("\n", " "))


def _row(cells) -> str:
    return "| " + " | ".join(_cell(c) for c in cells) + " |"


def claims_markdown(claims, details: bool = True) -> str:
    """The claims as Markdown: one short line per claim (its title, the verdict on the paper's
    protocol, the number that carries it), then each claim's
    :func:`~clap_unified.reproduce.claim_block` in
    a collapsed block (the book's front page shows the same); a deviation several claims
    share is listed by the first of them, the others refer to it ("as for claim 3 above").

    Examples
    --------
    >>> claim = {"key": "k", "title": "CLAP wins", "claim": "CLAP wins.", "section": "V",
    ...          "verdict": "reproduced", "summary": "reproduced", "headline": "CLAP 0.9",
    ...          "measured": "CLAP 0.9, RANSAC 0.5", "data": ["toy: 3 scenes"],
    ...          "chapter": "02_line_fitting"}
    >>> print(claims_markdown([claim], details=False))
    | # | claim | verdict on the paper's protocol | the number that carries it |
    |---|---|---|---|
    | 1 | CLAP wins | **reproduced** | CLAP 0.9 |
    <BLANKLINE>
    """
    lines = ["| # | claim | verdict on the paper's protocol | the number that carries it |",
             "|---|---|---|---|"]
    for i, c in enumerate(claims, 1):
        verdict = f"**{c['verdict']}**"
        if "verdict" in c and alternatives_count(c)["sensitivity"][0]:
            # the protocol's verdict depends on them: counted as every page counts them
            verdict += f"; {alternatives_text(c)}"
        lines.append(_row([i, c.get("title") or c["key"], verdict,
                           c.get("headline") or c["measured"]]))
    if details:
        shown = {}  # deviations listed by a block above: later blocks refer to it
        for i, c in enumerate(claims, 1):
            lines += ["", f"<details><summary>{i}. {c.get('title') or c['key']}: "
                      f"{c['verdict']}</summary>", "",
                      claim_block(c, shown, f"claim {i}").rstrip("\n"), "", "</details>"]
    return "\n".join(lines) + "\n"


def _controls_cell(controls) -> str:
    """The controls' verdicts, each marked when it did not reach the other verdict (or reached
    it mostly on pairs where both methods fail)."""
    marks = {"partly": " (did not decide: moved part of the way)", "no": " (did not decide)"}

    def mark(r):
        m = marks.get(r.get("reaches"), "")
        if m and r.get("weakens") == "CLAP" and r["verdict"] == "not reproduced":
            m = " (did not decide: it weakens CLAP, so it could only confirm the verdict)"
        if r.get("reaches") == "yes" and r.get("note"):  # decided, on pairs where both fail
            m = " (decided mostly on pairs where both methods fail)"
        return m

    return "; ".join(r["verdict"] + mark(r) for r in controls) or "-"


def verdicts_markdown(claims) -> str:
    """A short table of the verdicts: on the paper's protocol, how many alternatives reach
    another verdict (:func:`~clap_unified.reproduce.alternatives_text`, counted as every page
    counts them, and which verdicts, naming them when there are one or two, so that an
    unequal one is seen as such), and the controls' verdicts, each marked when it did not
    reach the other verdict. The decision guide shows it.

    Examples
    --------
    >>> claim = {"key": "k", "title": "CLAP wins", "verdict": "reproduced", "depends_on": [],
    ...          "sensitivity": [{"verdict": "reproduced"},
    ...                          {"verdict": "not reproduced", "label": "ten iterations: x"}],
    ...          "controls": [{"verdict": "not reproduced", "reaches": "yes"}]}
    >>> header, _, row = verdicts_markdown([claim]).splitlines()
    >>> print(header)
    | claim | on the paper's protocol | alternatives | controls |
    >>> print(row.split(" | ")[2])
    1 of 2 alternatives, all of them readings of the protocol, reaches another verdict: 1 not
    reproduced (ten iterations)
    """
    lines = ["| claim | on the paper's protocol | alternatives | controls |",
             "|---|---|---|---|"]
    for c in claims:
        alt = c.get("sensitivity", [])
        moved = [r for r in alt if _differs(r, c["verdict"])]
        flips = [r["verdict"] for r in moved]
        changed = alternatives_text(c) + (": " + ", ".join(
            f"{flips.count(v)} {v}" for v in dict.fromkeys(flips)) if flips else "")
        if 0 < len(moved) <= 2:  # few: say which, so an unequal one is seen as such
            changed += " (" + "; ".join(_variant_words(c, r) for r in moved) + ")"
        lines.append(_row([c.get("title") or c["key"], f"**{c['verdict']}**", changed,
                           _controls_cell(c.get("controls", []))]))
    return "\n".join(lines) + "\n"


def _variant_words(claim: dict, row: dict) -> str:
    """An alternative in a few words (:func:`~clap_unified.reproduce.describe_variant`), or
    the start of its label when its claim or key is not a registered one."""
    try:
        return describe_variant(claim["key"], row["key"])
    except (KeyError, ValueError):
        return str(row.get("change") or row.get("label") or row.get("key", "?")).split(":")[0]


def _write_report(out: Path, outputs: dict, claims: list, quick: bool) -> None:
    # No backend switch: in a notebook that would silently drop the figures drawn after the
    # call; each figure here is saved to bytes and closed, so no backend ever shows it.
    import matplotlib
    import matplotlib.pyplot as plt

    written = set()

    def write(path, data):
        write_atomic(path, data)
        written.add(path)

    for n in sorted(outputs):
        output = outputs[n]
        for t, rows in output.get("tables", {}).items():
            write(out / "tables" / f"{n}_{t}.csv", _csv(rows))
        ex = EXPERIMENTS[n]
        if ex.figures is None:
            continue
        for fname, fig in ex.figures(output).items():
            fig.text(0.005, 0.005, "data: " + output["data"].split(":")[0]
                     + (" (quick run)" if quick else ""), fontsize=6, color="0.4")
            # fixed SVG ids and no dates: the same figure gives the same bytes
            with matplotlib.rc_context({"svg.hashsalt": "clap_unified"}):
                for ext, meta in (("png", {"Software": None}), ("svg", {"Date": None})):
                    buf = io.BytesIO()
                    fig.savefig(buf, format=ext, dpi=110, metadata=meta)
                    write(out / "figures" / f"{fname}.{ext}", buf.getvalue())
            plt.close(fig)
    # files of an earlier run that this report does not hold would mix two runs
    for folder, pattern in (("tables", "*.csv"), ("figures", "*.png"), ("figures", "*.svg")):
        for stale in (out / folder).glob(pattern):
            if stale not in written:
                stale.unlink()
    write_atomic(out / "claims.json", _dumps({"mode": "quick" if quick else "full",
                                              "claims": claims}))
    write_atomic(out / "claims.md", "# Claims of the paper and what was measured\n\n"
                 + claims_markdown(claims))
