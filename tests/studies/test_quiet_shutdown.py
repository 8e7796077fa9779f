"""The package's own LocalCluster keeps the two records its workers log when the cluster is closed
under them (a Ctrl-C: the heartbeat finding the scheduler gone, with a traceback; a sample cancelled
in flight) off the user's terminal, and nothing else: the Ctrl-C tests of
test_study_infrastructure.py saw the heartbeat's traceback now and then, by timing."""

import logging

from cablecasing_core.studies.executor import Workers, _ShutdownNoise


def _record(name, level, text):
    return logging.LogRecord(name, level, __file__, 1, text, (), None)


def test_the_filter_drops_the_shutdown_records_only():
    noise = _ShutdownNoise()
    assert not noise.filter(
        _record("distributed.worker", logging.ERROR, "Failed to communicate with scheduler during heartbeat.")
    )
    assert not noise.filter(
        _record(
            "distributed.worker.state_machine",
            logging.WARNING,
            "Async instruction for <Task x> ended with CancelledError",
        )
    )
    for text in ("Worker process died", "Async instruction for <Task x> ended with ValueError", "Compute Failed"):
        assert noise.filter(_record("distributed.worker", logging.ERROR, text)), text


def test_the_workers_of_the_own_cluster_have_it():
    with Workers("local", 1) as w:
        got = w.client.run(lambda: [type(f).__name__ for f in logging.getLogger("distributed.worker").filters])
    assert list(got.values()) == [["_ShutdownNoise"]]
