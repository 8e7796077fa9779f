"""One check of the scheduler serves the study and the executor's Workers (which the ensemble
runs through): the same values refused with the same message before anything is made, a
distributed.Client and its subclasses taken by both, told apart from another class of that name."""

import os

import pytest

from cablecasing_core.errors import ModelError
from cablecasing_core.studies import run_study
from cablecasing_core.studies.executor import Workers, check_scheduler

distributed = pytest.importorskip("distributed")


class Client:  # (a class of the name from elsewhere: not dask's)
    pass


class MyClient(distributed.Client):
    pass


@pytest.mark.parametrize("bad", [42, b"tcp://127.0.0.1:8786", Client(), ["serial"]])
def test_the_study_and_the_workers_refuse_the_same_schedulers_alike(tmp_path, bad):
    path = tmp_path / "study.csv"
    with pytest.raises(ModelError) as study:
        run_study(
            str(path),
            evaluate="cablecasing_core.studies._stand_ins:analytic_evaluate",
            n_samples=24,
            scheduler=bad,
            progress=False,
        )
    with pytest.raises(ModelError) as workers:
        Workers(bad)
    assert str(study.value) == str(workers.value)
    assert str(study.value).startswith("scheduler = ") and "or a distributed.Client" in str(study.value)
    assert os.listdir(tmp_path) == []  # (refused before any file)


def test_a_subclass_of_distributeds_client_is_a_client():
    client = MyClient.__new__(MyClient)  # (not connected: the check looks at its class only)
    check_scheduler(client)
    with Workers(client) as w:  # (a Client passed in is used, and left open)
        assert w.client is client
    for fine in (None, "serial", "local", "tcp://127.0.0.1:8786"):
        check_scheduler(fine)
