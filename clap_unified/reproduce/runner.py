"""Running the experiments (one process, joblib or Dask) and writing the results.

Every file is written atomically (a temporary file in the same folder, then
a rename), so an interrupted run leaves no half-written file; a finished
experiment is cached in ``DIR/experiments/<name>.json`` and reused by the
next run with the same parameters and the same code (:func:`code_fingerprint`)
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

from . import registry
from .claims import evaluate_claims
from .data import missing_datasets
from .registry import EXPERIMENTS, seed_for

__all__ = ["MissingDataError", "Reproduction", "claims_markdown", "reproduce", "run_experiment",
           "write_atomic"]

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
        with os.fdopen(fd, "wb") as f:
            f.write(data.encode() if isinstance(data, str) else data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def run_experiment(name: str, quick: bool, position: int = 0, bars: bool = True) -> dict:
    """Run one experiment with the seed of its name; ``{"name", "output", "seconds"}``."""
    registry._BAR.position, registry._BAR.enabled = position, bars
    ex = EXPERIMENTS[name]
    t0 = time.perf_counter()
    output = _json_data(ex.run(ex.params(quick), seed_for(name)))
    return {"name": name, "output": output, "seconds": time.perf_counter() - t0}


def _json_data(obj):
    """``obj`` as JSON data, non-finite floats as None: the same whether fresh or cached."""
    def clean(x):
        if isinstance(x, dict):
            return {str(k): clean(v) for k, v in x.items()}
        if isinstance(x, list | tuple):
            return [clean(v) for v in x]
        if isinstance(x, float | np.floating):
            return float(x) if np.isfinite(x) else None
        if isinstance(x, np.integer | np.bool_):
            return x.item()
        return x

    return json.loads(json.dumps(clean(obj), allow_nan=False))


@functools.cache
def code_fingerprint() -> str:
    """sha256 of the package's source and the data manifests: a change recomputes the cache."""
    import hashlib

    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    files = sorted(root.rglob("*.py")) + sorted((root.parent / "data").rglob("*.json"))
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
    return doc["output"] if isinstance(doc, dict) and doc.get("key") == key else None


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
    from distributed import Client

    try:
        return Client(address, timeout=f"{timeout}s", set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise OSError(f"--scheduler {address}: cannot reach a Dask scheduler within "
                      f"{timeout:g} s ({exc})") from None


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
        n: "data set " + ", ".join(d for d in EXPERIMENTS[n].datasets if d in missing)
           + " not available here" for n in skipped}))
    _write_report(out, outputs, result.claims, quick)
    result.seconds = time.perf_counter() - t0
    write_atomic(out / "timings.json", _dumps({"experiments": timings,
                                               "total_seconds": result.seconds}))
    log(f"reproduce: finished in {result.seconds:.0f} s ({len(result.ran)} run, "
        f"{len(result.reused)} reused, {len(result.skipped)} skipped)")
    return result


# -------------------------------------------------------------------- report
def _csv(rows) -> str:
    buf = io.StringIO()
    cols = list(dict.fromkeys(k for r in rows for k in r))
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in cols})
    return buf.getvalue()


def claims_markdown(claims) -> str:
    """The claims as a Markdown table (the book's front page shows the same).

    Examples
    --------
    >>> print(claims_markdown([{"claim": "CLAP wins.", "section": "V", "verdict": "reproduced",
    ...                         "measured": "CLAP 0.9, RANSAC 0.5", "data": ["toy: 3 scenes"],
    ...                         "chapter": "02_line_fitting"}]))
    | claim (the paper's words) | verdict | what was measured | data |
    |---|---|---|---|
    | CLAP wins. *(V)* | **reproduced** | CLAP 0.9, RANSAC 0.5 | toy |
    <BLANKLINE>
    """
    lines = ["| claim (the paper's words) | verdict | what was measured | data |",
             "|---|---|---|---|"]
    for c in claims:
        data = "; ".join(d.split(":")[0] for d in c["data"]) or "-"
        cells = [f"{c['claim']} *({c['section']})*", f"**{c['verdict']}**", c["measured"], data]
        lines.append("| " + " | ".join(s.replace("|", "\\|").replace("\n", " ")
                                        for s in cells) + " |")
    return "\n".join(lines) + "\n"


def _write_report(out: Path, outputs: dict, claims: list, quick: bool) -> None:
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    for n, output in outputs.items():
        for t, rows in output.get("tables", {}).items():
            write_atomic(out / "tables" / f"{n}_{t}.csv", _csv(rows))
        ex = EXPERIMENTS[n]
        if ex.figures is None:
            continue
        for fname, fig in ex.figures(output).items():
            fig.text(0.005, 0.005, "data: " + output["data"].split(":")[0]
                     + (" (quick run)" if quick else ""), fontsize=6, color="0.4")
            for ext, meta in (("png", {"Software": None}), ("svg", {"Date": None})):
                buf = io.BytesIO()
                fig.savefig(buf, format=ext, dpi=110, metadata=meta)
                write_atomic(out / "figures" / f"{fname}.{ext}", buf.getvalue())
            plt.close(fig)
    write_atomic(out / "claims.json", _dumps({"mode": "quick" if quick else "full",
                                              "claims": claims}))
    write_atomic(out / "claims.md", "# Claims of the paper and what was measured\n\n"
                 + claims_markdown(claims))
