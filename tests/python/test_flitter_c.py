"""flitter_c against the command line: the same bits, the documented
shapes, state round trips, located errors, independent simulations.

Run by meson (suite 'python') with PYTHONPATH at the build tree's python/
and FLITTER naming the built `flitter` command, FLITTER_SAMPLES the
samples/ folder.
"""
import os
import struct
import subprocess
import threading
import time

import numpy as np
import pytest

import flitter_c
from flitter_c import FlitterError, Symbol

FLITTER = os.environ.get("FLITTER", "flitter")
SAMPLES = os.environ.get("FLITTER_SAMPLES", os.path.join(os.path.dirname(__file__), "../../samples"))
PETRI = os.path.join(SAMPLES, "petri.fl")


def cli_dump(script, frames, *extra):
    out = subprocess.run([FLITTER, "run", "--quiet", "--frames", str(frames), "--dump-state", *extra,
                          script], check=True, capture_output=True, text=True)
    return out.stdout


def dump_entries(text):
    entries = {}
    for line in text.splitlines():
        if line.startswith("#") or " = " not in line:
            continue
        k, v = line.split(" = ", 1)
        entries[k] = v
    return entries


def bits(x):
    return struct.pack("<d", x)


def test_positions_match_cli_dump_bit_for_bit():
    dump = cli_dump(PETRI, 120)
    sim = flitter_c.load(PETRI)
    assert sim.step(120) == 120
    assert sim.frame == 119 and sim.frames == 120
    assert dump.startswith(f"# frame 119 time {sim.time!r}\n")
    assert sim.dump_state() == dump
    entries = dump_entries(dump)
    ids, pos = sim.positions("dish")
    vids, vel = sim.velocities(":dish")
    assert ids == vids
    assert pos.dtype == np.float64 and pos.shape == (81, 2) and vel.shape == (81, 2)
    # 80 cells by number in dump order (0, 1, 10, 11, ...), then the anchor
    assert ids[:4] == [0, 1, 10, 11] and ids[-1] == "centre"
    assert sorted(i for i in ids if isinstance(i, int)) == list(range(80))
    for i, p, v in zip(ids, pos, vel):
        key = f":dish;{i}" if isinstance(i, int) else f":dish;:{i}"
        want_p = [float(t) for t in entries[key].split(";")]
        want_v = [float(t) for t in entries[key + ";:velocity"].split(";")]
        assert [bits(x) for x in p] == [bits(x) for x in want_p], key
        assert [bits(x) for x in v] == [bits(x) for x in want_v], key


def test_nosimplify_and_fps_reach_the_runtime():
    dump = cli_dump(PETRI, 30, "--nosimplify", "--fps", "30")
    sim = flitter_c.load(PETRI, simplify=False, fps=30)
    sim.step(30)
    assert sim.dump_state() == dump
    assert sim.time == pytest.approx(29 / 30)


def test_no_particles_before_first_frame():
    sim = flitter_c.load(PETRI)
    ids, pos = sim.positions("dish")
    assert ids == [] and pos.shape == (0, 0)
    assert sim.frame == -1 and sim.time == 0.0 and sim.tree() is None


def test_state_round_trip():
    sim = flitter_c.load(PETRI)
    st = sim.state
    st["x"] = 0.1
    assert st["x"] == 0.1 and isinstance(st["x"], float)
    arr = np.array([1.5, -2.25, 1e-300, 3.0000000000000004])
    st[(Symbol("a"), 2)] = arr
    got = st[":a;2"]
    assert isinstance(got, np.ndarray) and got.shape == (4,)
    assert [bits(x) for x in got] == [bits(x) for x in arr]
    st["s"] = Symbol("hello")
    assert st["s"] == "hello" and isinstance(st["s"], Symbol)
    st["t"] = "two words"
    assert st["t"] == "two words" and not isinstance(st["t"], Symbol)
    with pytest.raises(ValueError):
        st["u"] = "12"  # would read back as the number 12
    assert "u" not in st
    assert len(st) == 4
    # dump order: the dump quotes strings, and '"' sorts before ':'
    assert list(st) == ["s", "t", "x", ":a;2"]
    del st["x"]
    assert "x" not in st and len(st) == 3
    with pytest.raises(KeyError):
        st["nothing"]
    # the script sees what Python wrote
    sim.load_text('!physics state=:p dimensions=1 time=time resolution=1/60\n'
                  '    !particle id=0 position=$(:start)\n', name="p.fl")
    st[":start"] = 7.5
    sim.step(2)  # the first frame only starts the system's clock
    ids, pos = sim.positions("p")
    assert ids == [0] and pos.tolist() == [[7.5]]


def test_malformed_script_raises_with_location(tmp_path):
    bad = tmp_path / "bad.fl"
    bad.write_text("let x = 1\n!physics state=:s\n    !particle id=0 position=1 + * 2\n")
    with pytest.raises(FlitterError) as info:
        flitter_c.load(str(bad))
    err = info.value
    assert (err.path, err.line, err.col) == (str(bad), 3, 33)
    assert err.message == "syntax error, unexpected '*'"
    assert f"{bad}:{err.line}:{err.col}: error:" in str(err)
    # the CLI reports the same location
    cli = subprocess.run([FLITTER, "run", "--frames", "1", str(bad)], capture_output=True, text=True)
    assert cli.returncode != 0 and f"{bad}:{err.line}:{err.col}: error:" in cli.stderr
    with pytest.raises(FlitterError) as info:
        flitter_c.load(str(tmp_path / "missing.fl"))
    assert "missing.fl" in str(info.value)


def test_two_simulations_are_independent():
    a = flitter_c.load(PETRI)
    b = flitter_c.load(PETRI)
    b.state["noise"] = 1.0
    for _ in range(60):
        a.step()
        b.step(2)
    assert a.dump_state() == cli_dump(PETRI, 60)
    assert dump_entries(b.dump_state()) == {**dump_entries(cli_dump(PETRI, 120)), '"noise"': "1"}


def test_two_simulations_in_two_threads():
    want = cli_dump(PETRI, 90)
    sims = [flitter_c.load(PETRI), flitter_c.load(PETRI)]
    threads = [threading.Thread(target=s.step, args=(90,)) for s in sims]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert [s.dump_state() for s in sims] == [want, want]


def test_save_and_load_state_continue_exactly(tmp_path):
    a = flitter_c.load(PETRI)
    a.step(60)
    path = tmp_path / "s.state"
    a.save_state(str(path))
    c = flitter_c.load(PETRI)
    c.load_state(str(path))
    c.step(60)
    assert c.dump_state() == cli_dump(PETRI, 120)
    path.write_text("garbage\n")
    with pytest.raises(FlitterError):
        c.load_state(str(path))
    assert c.dump_state() == cli_dump(PETRI, 120)


def test_tree():
    sim = flitter_c.load(PETRI)
    sim.step()
    root = sim.tree()
    assert root.kind == "root"
    phys = root.children[0]
    assert phys.kind == "physics" and phys.attrs["state"] == Symbol("dish")
    assert phys.attrs["dimensions"] == 2.0
    kinds = [c.kind for c in phys.children]
    assert kinds.count("particle") == 80 and kinds[0] == "anchor"
    assert phys.children[0].attrs["position"].tolist() == [0.0, 0.0]


def test_render_view_and_picture(tmp_path):
    sim = flitter_c.load(PETRI)
    sim.step(10)
    out = tmp_path / "view.png"
    sim.render(str(out))
    cli = tmp_path / "cli.png"
    subprocess.run([FLITTER, "run", "--quiet", "--frames", "10", "--view", str(cli), PETRI], check=True)
    assert out.read_bytes() == cli.read_bytes()
    pic = sim.picture(size=(64, 48))
    assert pic.shape == (48, 64, 4) and pic.dtype == np.uint8
    assert pic[..., 3].max() == 255


def test_gil_released_inside_one_frame():
    # One frame of 20000 colliding particles lasts a good part of a second.
    # While another thread is inside that single fl_step, this thread's
    # loop keeps running: its longest pause stays well below the frame's
    # length (holding the GIL would stall it for the whole frame).
    sim = flitter_c.Simulation(threads=1)
    sim.load_text("!physics state=:h dimensions=2 time=time resolution=1/60\n"
                  "    for i in ..20000\n"
                  "        !particle id=i position=uniform(:x)[i]*1000;uniform(:y)[i]*1000 radius=5\n"
                  "    !collision\n", name="heavy.fl")
    sim.step()
    spent = []

    def one_frame():
        t = time.perf_counter()
        sim.step()
        spent.append(time.perf_counter() - t)

    worker = threading.Thread(target=one_frame)
    worker.start()
    last, longest = time.perf_counter(), 0.0
    while worker.is_alive():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
    worker.join()
    assert sim.frames == 2
    if spent[0] < 0.1:
        pytest.skip(f"the frame took only {spent[0]:.3f} s: too short to tell")
    assert longest < spent[0] / 2, (longest, spent[0])


def tree_attr(sim, name):
    line = sim.tree_text().splitlines()[1]
    return dict(w.split("=", 1) for w in line.split()[1:])[name]


@pytest.mark.parametrize("value,want", [
    (-3, "-3"), (-0.5, "-0.5"), (2.5e-300, "2.5e-300"), (True, "1"), ([1, -2], "1;-2"),
    (np.array([0.1, -7.0]), "0.1;-7"), (None, "null"), (Symbol("sym"), ":sym"),
    ("-3", "-3"), ("", '""'), ("1:30", "90"), ("10k", "10000"), ("abc", '"abc"'),
    ([Symbol("a"), 1.5], ":a;1.5"), (["x", -1], '"x";-1'),
])
def test_defines_reach_the_script_as_values(value, want, tmp_path):
    # numbers bound exactly, text read as `flitter run -D` reads it (issue 59)
    sim = flitter_c.Simulation()
    sim.define("X", value)
    sim.load_text("!foo x=X\n", name="d.fl")
    sim.step()
    got = tree_attr(sim, "x") if want != "null" else ("null" if "x=" not in sim.tree_text() else "?")
    assert got == want
    if isinstance(value, str) and not isinstance(value, Symbol):
        # the same text through the command line gives the same value
        script = tmp_path / "d.fl"
        script.write_text("!foo x=X\n")
        cli = subprocess.run([FLITTER, "run", "--quiet", "--frames", "1", "--dump-tree", "-D", f"X={value}",
                              str(script)], check=True, capture_output=True, text=True)
        assert cli.stdout.splitlines()[1].split()[1] == f"x={want}"


def test_define_refuses_bad_names_and_nul():
    sim = flitter_c.Simulation()
    with pytest.raises(FlitterError, match="not a name"):
        sim.define("9x", 1)
    with pytest.raises(ValueError):
        sim.define("X\0Y", 1)
    with pytest.raises(ValueError):
        sim.define("X", "a\0b")
    with pytest.raises(ValueError):
        sim.define("X", Symbol("a;b"))
    with pytest.raises(ValueError):
        sim.load("dish\0.fl")
    with pytest.raises(ValueError):
        sim.load(b"dish\0.fl")


def test_paths_as_bytes_and_pathlike(tmp_path):
    # paths as os functions take them: str, bytes and os.PathLike (a bytes
    # path once raised AttributeError)
    script = tmp_path / "c.fl"
    script.write_text("!counter state=:n rate=1\n")
    for path in (str(script), os.fsencode(str(script)), script):
        sim = flitter_c.Simulation()
        sim.load(path)
        sim.step(2)
        state = tmp_path / "c.state"
        sim.save_state(os.fsencode(str(state)))
        sim.load_state(state)
        assert sim.frames == 2


def test_define_and_load_race_under_the_lock():
    # define and load from two threads: both take the simulation's lock, so
    # neither frees what the other uses (issue 60; ASan in the sanitizer
    # phase, a malloc abort before)
    sim = flitter_c.Simulation()
    stop = threading.Event()

    def defining():
        i = 0
        while not stop.is_set():
            sim.define("X", [i, -i])
            sim.define("Y", "a;b")
            i += 1

    t = threading.Thread(target=defining)
    t.start()
    try:
        for _ in range(200):
            sim.load(PETRI)
            sim.step()
            _ = sim.frames, sim.time, len(sim.state)
    finally:
        stop.set()
        t.join()
    assert sim.frames == 200
