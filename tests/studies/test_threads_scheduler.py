"""The threads scheduler's hand-over of warnings (studies/executor.py): each warning reaches the
sample of the thread that gave it, also when a sample runs a study of its own inside it."""

import threading
import warnings

from cablecasing_core.studies import executor


def test_a_study_inside_a_sample_on_a_thread_keeps_each_samples_warnings():
    got = {}

    def sample():
        executor._sample_thread()
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
