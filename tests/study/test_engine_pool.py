"""The pool that survives dead workers (:mod:`trikedyn.study.engine.pool`), shared by the sampled studies, the
loading chart and the optimiser."""

import os

import pytest

from trikedyn.study.engine.pool import MAX_RESTARTS, ResilientPool, WorkersKeptDying


def _square_or_die(x, deadly):
    """x squared; kills its worker process when x is in ``deadly`` (as a crash would)."""
    if x in deadly:
        os._exit(1)
    return x * x


def test_each_call_answers_once_in_this_process():
    got = {}
    pool = ResilientPool(0)
    try:
        pool.run(_square_or_die, ((x, (x, ())) for x in range(5)), got.__setitem__, pytest.fail)
    finally:
        pool.close()
    assert got == {x: x * x for x in range(5)}


def test_a_call_that_kills_its_worker_twice_is_given_up_the_others_answer():
    """The pool keeps one call more in flight than it has workers: a call sharing both deaths is given up too."""
    got, dead = {}, []
    pool = ResilientPool(1)
    try:
        pool.run(_square_or_die, ((x, (x, (3,))) for x in range(8)), got.__setitem__, dead.append)
    finally:
        pool.close()
    assert 3 in dead and len(dead) <= 2
    assert got == {x: x * x for x in range(8) if x not in dead}
    assert pool.restarts == 2


def test_workers_that_keep_dying_stop_the_run_naming_what_is_not_done():
    deadly = tuple(range(MAX_RESTARTS + 3))
    pool = ResilientPool(1)
    dead = []
    try:
        with pytest.raises(WorkersKeptDying) as caught:
            pool.run(_square_or_die, ((x, (x, deadly)) for x in deadly), pytest.fail, dead.append)
    finally:
        pool.close()
    assert pool.restarts == MAX_RESTARTS + 1
    assert "died 4 times" in str(caught.value)
    assert set(dead) | set(caught.value.remaining) == set(deadly)
