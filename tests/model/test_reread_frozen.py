"""A validated model's containers, FrozenDict and FrozenList: each refuses every mutator of its
type, copies to its plain type (shallow with copy.copy, all the way down with copy.deepcopy) and
stays frozen through pickling, as their docstrings say."""

import copy
import pickle

import pytest

import cablecasing_core as cc
from cablecasing_core.model.model import FrozenDict, FrozenList

MUTATORS = {
    FrozenDict: [
        ("__setitem__", "k", 1),
        ("__delitem__", "geometry"),
        ("__ior__", {}),
        ("clear",),
        ("pop", "geometry"),
        ("popitem",),
        ("setdefault", "k", 1),
        ("update", {}),
    ],
    FrozenList: [
        ("__setitem__", 0, 1),
        ("__delitem__", 0),
        ("__iadd__", []),
        ("__imul__", 2),
        ("append", 1),
        ("clear",),
        ("extend", []),
        ("insert", 0, 1),
        ("pop",),
        ("remove", 0),
        ("reverse",),
        ("sort",),
    ],
}


@pytest.fixture(scope="module")
def containers():
    data = cc.load_model().data
    return {FrozenDict: data, FrozenList: data["geometry"]["points"]}


@pytest.mark.parametrize("kind", [FrozenDict, FrozenList])
def test_a_frozen_container_refuses_changes_and_copies_plain(containers, kind):
    x = containers[kind]
    plain = dict if kind is FrozenDict else list
    assert type(x) is kind and isinstance(x, plain)
    before = copy.deepcopy(x)
    for name, *args in MUTATORS[kind]:
        with pytest.raises(TypeError, match="read-only"):
            getattr(x, name)(*args)
    assert x == before
    shallow = copy.copy(x)
    assert type(shallow) is plain and shallow == x
    deep = copy.deepcopy(x)
    assert type(deep) is plain and deep == x
    inner = next(iter(deep.values())) if plain is dict else deep[0]
    assert type(inner) in (dict, list)  # (a plain copy all the way down: yours to change)
    back = pickle.loads(pickle.dumps(x))
    assert type(back) is kind and back == x
    with pytest.raises(TypeError, match="read-only"):
        back.clear()
