"""The executor of the studies: one sample in this process or on a dask.distributed worker, and the
loop over all samples, serial or on dask (the Monte-Carlo study and the seed ensemble both run
through :func:`execute`)."""

from __future__ import annotations

import importlib
import os
import time

from ..errors import ModelError
from ..model.validators import integer


def resolve_evaluate(spec):
    """The per-sample function of the study (Section 4.4) named by ``spec``: a callable (returned as
    is) or ``"package.module:function"`` (also ``"package.module.function"``). Raises ModelError if
    it cannot be imported."""
    if callable(spec):
        return spec
    if not isinstance(spec, str) or not spec:
        raise ModelError("evaluate", spec, "must be a callable or a dotted import path 'package.module:function'")
    mod_name, sep, attr = spec.partition(":")
    if not sep:
        mod_name, _, attr = spec.rpartition(".")
    try:
        fn = getattr(importlib.import_module(mod_name), attr)
    except (ImportError, AttributeError, ValueError) as exc:
        raise ModelError(
            "evaluate", spec, f"must name an importable function 'package.module:function' ({exc})"
        ) from None
    if not callable(fn):
        raise ModelError("evaluate", spec, "must name a callable")
    return fn


def spec_name(spec):
    if isinstance(spec, str):
        return spec
    return f"{getattr(spec, '__module__', '?')}:{getattr(spec, '__qualname__', repr(spec))}"


def evaluate_sample(spec, kwargs, index, overrides, outputs):
    """Run one sample (in the main process or on a dask worker); never raises for an Exception."""
    t0 = time.perf_counter()
    row = {"index": index, "status": "ok", "error": ""}
    try:
        res = resolve_evaluate(spec)(dict(overrides), **kwargs)
        if not isinstance(res, dict):
            raise TypeError(f"evaluate returned {type(res).__name__}, expected dict of output name -> float")
        missing = [o for o in outputs if o not in res]
        if missing:
            raise KeyError(f"evaluate returned no value for {missing}; it gave {sorted(res)}")
        for o in outputs:
            row[o] = float(res[o])
    except Exception as exc:  # a failed sample is recorded, the study goes on
        row = {"index": index, "status": "failed", "error": f"{type(exc).__name__}: {exc}".replace("\n", " | ")}
    row["elapsed_s"] = time.perf_counter() - t0
    return row


def execute(todo, evaluate, kwargs, outputs, writer, bar, scheduler, n_workers=None, max_in_flight=None):
    """Evaluate the samples ``todo`` = [(index, overrides), ...] with ``evaluate(overrides, **kwargs)``
    in this process (``scheduler="serial"``) or on dask, passing each row to ``writer.write`` as it
    completes and counting it on ``bar``. A failed sample is a row with status "failed"."""
    if scheduler == "serial":
        for i, p in todo:
            writer.write(evaluate_sample(evaluate, kwargs, i, p, outputs))
            bar.update(1)
    else:
        _run_dask(todo, evaluate, kwargs, outputs, writer, bar, scheduler, n_workers, max_in_flight)


def _run_dask(todo, evaluate, kwargs, outputs, writer, bar, scheduler, n_workers, max_in_flight):
    """Submit the samples to dask.distributed and write each result as it completes."""
    from distributed import Client, LocalCluster, as_completed

    own_client = cluster = None
    if scheduler is None or scheduler == "local":
        nw = os.cpu_count() if n_workers is None else integer("n_workers", n_workers, 1)
        cluster = LocalCluster(n_workers=nw, threads_per_worker=1, processes=True, dashboard_address=None)
        client = own_client = Client(cluster)
    elif isinstance(scheduler, str):
        try:
            client = own_client = Client(scheduler, timeout="30s")
        except (OSError, ValueError) as exc:
            raise ModelError(
                "scheduler",
                scheduler,
                f"must be 'serial', 'local' or a reachable scheduler address such as tcp://host:8786 ({exc})",
            ) from None
    elif isinstance(scheduler, Client):
        client = scheduler
    else:
        raise ModelError(
            "scheduler",
            scheduler,
            "must be None, 'serial', 'local', an address 'tcp://host:8786' or a distributed.Client",
        )
    try:
        if not todo:
            return
        nthreads = max(1, sum(client.nthreads().values()))
        window = max_in_flight or 4 * nthreads
        pending = iter(todo)
        ac = as_completed()
        keyed = {}

        def submit_next():
            item = next(pending, None)
            if item is None:
                return
            i, p = item
            fut = client.submit(evaluate_sample, evaluate, kwargs, i, p, outputs, pure=False)
            keyed[fut.key] = i
            ac.add(fut)

        for _ in range(window):
            submit_next()
        for fut in ac:
            i = keyed.pop(fut.key)
            try:
                row = fut.result()
            except Exception as exc:  # e.g. a worker died: record and go on
                row = {
                    "index": i,
                    "status": "failed",
                    "error": f"{type(exc).__name__}: {exc}".replace("\n", " | "),
                    "elapsed_s": float("nan"),
                }
            fut.release()
            writer.write(row)
            bar.update(1)
            submit_next()
    finally:
        if own_client is not None:
            own_client.close()
        if cluster is not None:
            cluster.close()
