"""The module under test is the repository's (python/), the programs are
the build's ($TIS_BIN, else PATH), as for every other test of the suite."""
import os
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
TOP = os.path.dirname(os.path.dirname(HERE))

import tis  # noqa: E402


def tool(*args, input=None, check=True):
    """Run a program: (stdout bytes, stderr bytes, status)."""
    r = subprocess.run([tis.tool_path(args[0])] + [str(a) for a in args[1:]], input=input,
                       capture_output=True)
    if check and r.returncode != 0:
        raise AssertionError("%s: exit %d: %s" % (args, r.returncode, r.stderr.decode()))
    return r.stdout, r.stderr, r.returncode


@pytest.fixture(scope="session")
def top():
    return TOP


@pytest.fixture(scope="session")
def work(tmp_path_factory):
    """Meshes the tests share: a honeycomb at p_hex with its first
    junction's active run in frames (--every), and a stopped anneal."""
    d = tmp_path_factory.mktemp("tis")
    out, _, _ = tool("tis-hex", 4, 4)
    (d / "hex.mesh").write_bytes(out)
    out, _, _ = tool("tis-relax", "--quiet", "--p0", "3.7224194", d / "hex.mesh")
    (d / "phex.mesh").write_bytes(out)
    out, _, _ = tool("tis-active", "--index", 0, "--rate", 0.19, "--gamma0", 0.11, "--time", 40,
                     "--every", 5, "--trace", d / "trace.tsv", d / "phex.mesh")
    (d / "frames.mesh").write_bytes(out)
    out, _, _ = tool("tis-active", "--network", "--time", 20, "--seed", 2, "--gamma0", 0.1,
                     "--sigma", 0.05, "--every", 5, "--events", d / "events.tsv", d / "phex.mesh")
    (d / "network.mesh").write_bytes(out)
    return d
