"""`btgen compile` writes its outputs atomically, all or none, and only when they change.

Each claim of compiler.py's docstring has a test here:

- a failed compile (invalid mission, mission the back end rejects, an output
  that cannot be written) leaves the previous outputs byte-identical and no
  temporary file behind;
- an unchanged output is not rewritten (its mtime stays);
- a compile that dies at any point (a fault injected at every file system
  step; SIGKILL of a real `btgen compile` at random moments) never leaves a
  partial output: each file holds one complete generation.
"""

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from btgen import compiler
from btgen.diagnostics import UserError

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="{name}">
      <Move/>
      <Retry num_attempts="{n}"><IsReady/></Retry>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel><Action ID="Move"/><Condition ID="IsReady"/></TreeNodesModel>
</root>
""".replace("<Retry", "<RetryUntilSuccessful").replace("</Retry>", "</RetryUntilSuccessful>")


def _compile(mission, out_dir, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "btgen", "compile", str(mission), "-o", str(out_dir)],
        cwd=cwd,
        capture_output=True,
        check=False,
        timeout=120,
    )


def _snapshot(out_dir):
    return {
        p.name: (b"<dir>" if p.is_dir() else p.read_bytes(), p.stat().st_mtime_ns, p.stat().st_mode)
        for p in sorted(Path(out_dir).iterdir())
    }


def _in_process(mission, out_dir):
    import argparse

    return compiler.compile_command(argparse.Namespace(mission=str(mission), output_dir=str(out_dir), relative_to=None))


@pytest.fixture
def compiled(tmp_path, monkeypatch):
    """A mission compiled once into out/; outputs back-dated so that a rewrite shows."""
    monkeypatch.chdir(tmp_path)
    mission = tmp_path / "atomic_probe.xml"
    mission.write_text(MISSION.format(name="First", n=2))
    out = tmp_path / "out"
    assert _compile(mission.name, out, cwd=tmp_path).returncode == 0
    for p in out.iterdir():
        os.utime(p, ns=(1_000_000_000_000_000_000, 1_000_000_000_000_000_000))
    return mission, out


def test_compile_writes_the_outputs(compiled):
    mission, out = compiled
    assert sorted(p.name for p in out.iterdir()) == ["atomic_probe.cpp", "atomic_probe.hpp"]
    assert b"First" in (out / "atomic_probe.hpp").read_bytes()


def test_outputs_get_the_usual_permissions(compiled):
    """Temporary files are created 0600; the outputs must still be readable as the umask allows."""
    mission, out = compiled
    umask = os.umask(0)
    os.umask(umask)
    for p in out.iterdir():
        assert p.stat().st_mode & 0o777 == 0o666 & ~umask, p


def test_unchanged_output_keeps_its_mtime(compiled):
    mission, out = compiled
    before = _snapshot(out)
    assert _compile(mission.name, out, cwd=mission.parent).returncode == 0
    assert _snapshot(out) == before
    mission.write_text(MISSION.format(name="Second", n=2))
    assert _compile(mission.name, out, cwd=mission.parent).returncode == 0
    after = _snapshot(out)
    assert after["atomic_probe.hpp"][0] != before["atomic_probe.hpp"][0]
    assert after["atomic_probe.hpp"][1] != before["atomic_probe.hpp"][1]


@pytest.mark.parametrize(
    "broken",
    [
        MISSION.format(name="Broken", n=2).replace("</Sequence>", ""),  # not well-formed
        MISSION.format(name="Broken", n="two"),  # fails validation
        # valid, but the C++ back end rejects it (a SetBlackboard whose key is read from an entry
        # that a script gives a value btgen cannot know before the run)
        MISSION.format(name="Broken", n=2).replace(
            "<Move/>",
            '<Script code="target := \'x\'; target += \'y\'"/><SetBlackboard value="1" output_key="{target}"/>',
        ),
    ],
)
def test_failed_compile_leaves_previous_output_byte_identical(compiled, broken):
    mission, out = compiled
    before = _snapshot(out)
    mission.write_text(broken)
    proc = _compile(mission.name, out, cwd=mission.parent)
    assert proc.returncode == 1, proc.stderr
    assert proc.stderr.startswith(b"atomic_probe.xml:"), proc.stderr
    assert _snapshot(out) == before


def test_an_output_that_cannot_be_written_changes_nothing(compiled):
    """The second output cannot be replaced (a directory is in its way): the first must not change either."""
    mission, out = compiled
    (out / "atomic_probe.cpp").unlink()
    (out / "atomic_probe.cpp").mkdir()
    before = _snapshot(out)
    mission.write_text(MISSION.format(name="Second", n=3))
    proc = _compile(mission.name, out, cwd=mission.parent)
    assert proc.returncode == 1
    assert b"out/atomic_probe.cpp:1:1: error: cannot write the generated file" in proc.stderr, proc.stderr
    assert _snapshot(out) == before


@pytest.mark.parametrize("step", range(12))
def test_a_fault_at_any_step_leaves_one_generation(compiled, monkeypatch, step):
    """Make the k-th file system operation of the write phase fail: all outputs stay as they were."""
    mission, out = compiled
    before = _snapshot(out)
    mission.write_text(MISSION.format(name="Second", n=3))
    calls = {"n": 0}

    def faulty(real):
        def op(*args, **kwargs):
            calls["n"] += 1
            if calls["n"] == step + 1:
                raise OSError(5, "injected fault")
            return real(*args, **kwargs)

        return op

    for name in ("replace", "rename", "fsync", "chmod", "fdopen", "unlink"):
        if hasattr(compiler.os, name):
            monkeypatch.setattr(compiler.os, name, faulty(getattr(os, name)))
    monkeypatch.setattr(compiler.tempfile, "mkstemp", faulty(compiler.tempfile.mkstemp))
    try:
        _in_process(mission.name, out)
        failed = False
    except UserError:
        failed = True
    monkeypatch.undo()
    after = _snapshot(out)
    if failed:
        assert after == before, f"fault at step {step + 1} left a mixed state"
    else:  # fewer steps than `step`: the compile completed
        assert calls["n"] <= step
        assert b"Second" in after["atomic_probe.hpp"][0]
    assert sorted(after) == ["atomic_probe.cpp", "atomic_probe.hpp"], "a temporary file was left behind"


def test_sigkill_at_random_moments_never_leaves_a_partial_file(tmp_path):
    """Kill real compiles at random moments, alternating two missions: every output is always one
    complete generation of one of them."""
    mission = tmp_path / "atomic_probe.xml"
    out = tmp_path / "out"
    versions = [MISSION.format(name=f"V{i}" * 2000, n=i + 1) for i in range(2)]  # large outputs
    expected = []
    for text in versions:
        mission.write_text(text)
        ref = tmp_path / f"ref{len(expected)}"
        assert _compile(mission.name, ref, cwd=tmp_path).returncode == 0
        expected.append({p.name: p.read_bytes() for p in ref.iterdir()})
    rng = random.Random(8)
    start = time.monotonic()
    t0 = time.monotonic()
    assert _compile(mission.name, out, cwd=tmp_path).returncode == 0
    full = time.monotonic() - t0
    kills = 0
    for i in range(40):
        mission.write_text(versions[i % 2])
        proc = subprocess.Popen(
            [sys.executable, "-m", "btgen", "compile", mission.name, "-o", str(out)],
            cwd=tmp_path,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        time.sleep(rng.uniform(0.5, 1.0) * full)
        if proc.poll() is None:
            proc.send_signal(signal.SIGKILL)
            kills += 1
        proc.wait()
        for p in out.iterdir():
            if p.name.endswith(".tmp"):
                continue  # SIGKILL cannot clean up; a hidden temporary file is not an output
            assert any(p.read_bytes() == e.get(p.name) for e in expected), f"{p.name} is partial after kill {i}"
        if time.monotonic() - start > 60:
            break
    assert kills > 0, "no compile was killed: the timing is off"
