"""Threads against one flitter_c.Simulation: every method that touches the
runtime takes the simulation's lock, so calls from several threads at once
interleave whole. Runs in suite 'python' and, in the sanitizer build, again
under ASan+UBSan (suite 'python-asan', tests/meson.build), where a method
without the lock shows as a use after free.
"""
import os
import threading

import flitter_c
from flitter_c import FlitterError

SAMPLES = os.environ.get("FLITTER_SAMPLES", os.path.join(os.path.dirname(__file__), "../../samples"))
PETRI = os.path.join(SAMPLES, "petri.fl")
ROUNDS = 60


def test_every_method_from_four_threads(tmp_path):
    sim = flitter_c.Simulation(threads=1)
    sim.load(PETRI)
    errors = []
    start = threading.Barrier(4)

    def guarded(body):
        def run():
            start.wait()
            try:
                for i in range(ROUNDS):
                    body(i)
            except Exception as e:  # pragma: no cover - reported below
                errors.append(repr(e))
        return run

    def loading(i):
        if i % 3 == 0:
            sim.load(PETRI)
        else:
            sim.load_text("!window\n    !canvas\n        !rect size=%d;4\n" % (i + 1), "t%d.fl" % i)
        sim.step()

    def defining(i):
        sim.define("X", [i, -i])
        sim.define("Y", "a;b")
        sim.state["k%d" % (i % 5)] = float(i)
        _ = dict(sim.state.items_text())
        if i % 7 == 0:   # (another thread's load_state may have taken it already)
            sim.state.pop("k%d" % (i % 5), None)

    def reading(i):
        _ = sim.frames, sim.frame, sim.time
        _ = sim.dump_state()
        _ = sim.tree_text()
        _ = sim.tree()

    def saving(i):
        path = str(tmp_path / ("s%d.state" % (i % 2)))
        sim.save_state(path)
        try:
            sim.load_state(path)
        except FlitterError:
            pass   # a state saved by another program's load: refused, never a crash

    threads = [threading.Thread(target=guarded(f)) for f in (loading, defining, reading, saving)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    # and the simulation goes on stepping
    sim.load(PETRI)
    before = sim.frames
    sim.step(3)
    assert sim.frames == before + 3


def test_pop_is_one_step():
    """State.pop reads then deletes; another thread's delete may not come
    between them. Thread A's read signals thread B to delete the key and
    waits up to 0.3 s for it: with the lock held through pop, B waits until
    A is done, A gets the value and B finds nothing to delete; without it,
    B deletes first and A's own delete raises KeyError."""
    sim = flitter_c.Simulation(threads=1)
    sim.load_text("!window\n", "t.fl")
    st = sim.state
    st["k"] = 5.0
    read, deleted = threading.Event(), threading.Event()
    plain_getitem = type(st).__getitem__

    class Probe(type(st)):
        def __getitem__(self, key):
            value = plain_getitem(self, key)
            read.set()
            deleted.wait(0.3)
            return value

    st.__class__ = Probe
    b_result = []

    def other():
        read.wait(5)
        b_result.append(st.pop("k", "gone"))
        deleted.set()

    b = threading.Thread(target=other)
    b.start()
    assert st.pop("k", None) == 5.0
    b.join()
    assert b_result == ["gone"]
    assert "k" not in st
