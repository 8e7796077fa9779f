"""The threads scheduler's hand-over of warnings (studies/executor.py): each warning reaches the
sample of the thread that gave it, also when a sample runs a study of its own inside it."""

import threading
import warnings

from cablecasing_core.studies import executor


def test_a_study_inside_a_sample_on_a_thread_keeps_each_samples_warnings():
    got = {}

    def sample():
        executor._sample_thread(None)
        with executor._recorded() as outer:
            warnings.warn("before", UserWarning, stacklevel=1)
            with executor._recorded() as inner:  # (a study run by the sample's evaluate)
                warnings.warn("inside", UserWarning, stacklevel=1)
            warnings.warn("after", UserWarning, stacklevel=1)
        got["outer"], got["inner"] = [str(w.message) for w in outer], [str(w.message) for w in inner]

    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        with executor._warnings_by_thread():
            t = threading.Thread(target=sample)
            t.start()
            t.join()
            warnings.warn("the caller's own", UserWarning, stacklevel=1)  # (not a sample's: shown)
    assert got == {"outer": ["before", "after"], "inner": ["inside"]}
    assert [str(w.message) for w in shown] == ["the caller's own"]


def test_a_run_stopped_from_another_thread_ends_at_its_next_chunk_and_leaves_the_engine_as_it_was():
    """stop_runs_on: the event set while a run is under way (here by its own motion, at a known
    chunk, so that nothing depends on timing) ends Engine.advance before the next chunk of
    Engine.CHUNK steps with RunStopped, and the engine is as it was before the call (time, state,
    no recorded history), so it can be advanced again."""
    import numpy as np

    import cablecasing_core as cc
    from cablecasing_core.errors import RunStopped
    from cablecasing_core.timedomain.engine import Engine, stop_runs_on
    from cablecasing_core.timedomain.scenario import scenario_motion

    model = cc.load_model()
    grid = scenario_motion(model, dt=1e-5)
    stop = threading.Event()
    seen = []

    def motion(t):
        seen.append(t[-1])
        if len(seen) == 2:  # (the first chunk's motion; the first call is the run's start, t = 0)
            stop.set()
        return grid(t)

    got = {}

    def run():
        stop_runs_on(stop)
        eng = Engine(model, ledger=False, record=True)
        before = eng.get_state()
        try:
            eng.advance(1.0, motion)  # (100 000 steps: 49 chunks)
        except RunStopped as exc:
            got["stopped"] = str(exc)
        got["same"] = all(np.array_equal(v, eng.get_state()[k]) for k, v in before.items())
        got["time"], got["history"] = eng.time, len(eng._hist)
        stop.clear()
        eng.advance(1e-4, grid)  # (the engine still runs)
        got["after"] = eng.time

    t = threading.Thread(target=run)
    t.start()
    t.join()
    chunk = Engine.CHUNK * 1e-5
    # (the first chunk runs to its end, the stop is seen before the second)
    assert got["stopped"] == f"stopped at t = {chunk:.6g} s" and len(seen) == 2, (got, seen)
    assert got["same"] and got["time"] == 0.0 and got["history"] == 0, got
    assert abs(got["after"] - 1e-4) < 1e-15


def test_ctrl_c_stops_the_samples_in_progress_on_threads():
    """Ctrl-C in the threads scheduler (here a KeyboardInterrupt from the writer, on the first row
    written) cancels the samples not begun and stops the one in progress, which would never end on
    its own (its evaluate runs 0.05 s records in a loop until it is stopped), at its run's next
    chunk: its thread ends, and the interrupt reaches the caller."""
    import cablecasing_core as cc

    model = cc.load_model()
    begun, running, given_up = [], threading.Event(), threading.Event()

    def evaluate(overrides, **_):
        begun.append(overrides["i"])
        if overrides["i"] == 0:
            # (its row, the interrupt's, once sample 1 is under way: sample 1 sets it first thing, before any run,
            # so only a thread's start is waited for, well under 30 s on a loaded machine; a scheduler that keeps
            # one sample in flight never begins sample 1, and the test fails after those 30 s)
            running.wait(timeout=30)
            return {"y": 1.0}
        running.set()
        while not given_up.is_set():  # (never returns while the test waits: only the stop ends it)
            cc.simulate(model, duration=0.05)
        return {"y": 2.0}

    class Interrupting:
        def write(self, row):
            raise KeyboardInterrupt

    class Bar:
        def update(self, n):
            pass

    todo = [(i, {"i": i}) for i in range(5)]
    try:
        executor.execute(todo, evaluate, {}, ["y"], Interrupting(), Bar(), "threads", n_workers=2)
    except KeyboardInterrupt:
        pass
    else:
        raise AssertionError("the interrupt did not reach the caller")
    workers = [t for t in threading.enumerate() if t.name.startswith("cablecasing-sample")]
    try:
        for w in workers:
            w.join(timeout=60)  # (a chunk of 2048 steps takes ~20 ms; the sample alone never ends)
        assert not any(w.is_alive() for w in workers), workers
    finally:
        given_up.set()  # (so that a failure ends the thread, and not the test run)
    assert sorted(begun) == [0, 1], begun  # (2, 3 and 4 never begun)
