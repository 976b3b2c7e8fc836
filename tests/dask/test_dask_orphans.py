"""A Dask worker that dies mid-shard leaves no `entrynav` child running and no shard file behind.

The worker is modelled by a Python process that runs the shard task function of
scripts/dask_trade.py (what a Dask worker thread runs) and is then killed with SIGKILL, as the OOM
killer or a lost nanny would kill a worker."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ENTRYNAV = os.environ.get("ENTRYNAV", str(ROOT / "target" / "release" / "entrynav"))


def children_of(pid):
    """PIDs of the live processes whose parent is `pid` (from /proc)."""
    out = []
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            fields = (d / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid and fields[0] != "Z":
            out.append(int(d.name))
    return out


def alive(pid):
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def test_killed_worker_leaves_no_orphan(tmp_path):
    worker = subprocess.Popen(
        [sys.executable, "-c",
         "import sys; sys.path.insert(0, sys.argv[1]); import dask_trade; "
         "dask_trade.run_shard(sys.argv[2], 'orbiters-3', 'ekf', 10**7, 1, 0, 1, [])",
         str(ROOT / "scripts"), ENTRYNAV],
        cwd=tmp_path)
    try:
        child = None
        for _ in range(200):
            kids = children_of(worker.pid)
            if kids:
                child = kids[0]
                break
            time.sleep(0.05)
        assert child is not None, "the shard task started no entrynav"
        # A child caught between fork and exec (or inside execve) shows an empty or the parent's
        # command line for a moment: read it until it is the exec'd entrynav's.
        cmdline = ""
        for _ in range(100):
            try:
                cmdline = Path(f"/proc/{child}/cmdline").read_bytes().decode(errors="replace")
            except OSError:
                cmdline = ""
            if cmdline.split("\0", 1)[0].endswith("entrynav"):
                break
            time.sleep(0.02)
        assert cmdline.split("\0", 1)[0].endswith("entrynav"), f"child {child} runs {cmdline!r}"
        time.sleep(0.5)  # the shard is running
        os.kill(worker.pid, signal.SIGKILL)
        worker.wait(timeout=10)
        deadline = time.time() + 5
        while alive(child) and time.time() < deadline:
            time.sleep(0.05)
        orphan = alive(child)
        if orphan:
            os.kill(child, signal.SIGKILL)
        assert not orphan, f"entrynav {child} still runs after its worker was killed"
        # The shard went to a pipe: nothing was written where the worker ran.
        assert list(tmp_path.iterdir()) == []
    finally:
        if worker.poll() is None:
            worker.kill()
