"""The tools from Python: meshes in and out through pipes, as in a shell
pipeline, no temporary files.

    relaxed = tis.run(["tis-relax", "--p0", "3.7"], mesh)
    fit = tis.pipeline(mesh, ["tis-relax", "--p0", "3.7"],
                       ["tis-forcelen", "--index", "0"], ["tis-fit"])

The programs are found in $TIS_BIN if it is set, else on PATH.
"""

import io
import os
import shutil
import subprocess
import threading

from .mesh import Mesh, read_meshes, _format
from .table import read_table


class ToolError(RuntimeError):
    """A tool exited with a status other than 0: .status, .message (its
    stderr, "tis-foo: what went wrong"), .args_ (its command line) and
    .stdout (what it wrote: a stopped run writes its last state)."""

    def __init__(self, cmd, status, message, stdout=b""):
        self.status, self.message, self.args_, self.stdout = status, message.strip(), cmd, stdout
        super().__init__("%s: exit %d: %s" % (cmd[0], status, self.message or "(no message)"))


def tool_path(name):
    """The program name as the suite's tests find it: $TIS_BIN/name, else PATH."""
    if os.sep in name:
        return name
    d = os.environ.get("TIS_BIN")
    if d and os.access(os.path.join(d, name), os.X_OK):
        return os.path.join(d, name)
    p = shutil.which(name)
    if p is None:
        raise FileNotFoundError("%s: not found (build the suite, or set TIS_BIN or PATH)" % name)
    return p


def _input_bytes(x):
    if x is None:
        return b""
    if isinstance(x, Mesh):
        x = _format(x)
    elif isinstance(x, (list, tuple)) and x and all(isinstance(m, Mesh) for m in x):
        x = "".join(_format(m) for m in x)
    if isinstance(x, str):
        x = x.encode("utf-8", "surrogateescape")
    return bytes(x)


def _output(data, output):
    text = data.decode("utf-8", "surrogateescape")
    if output == "auto":
        first = next((ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")), "")
        if first.split() == ["tismesh", "1"]:
            output = "meshes"
        elif "\t" in first:
            output = "table"
        else:
            output = "text"
    if output in ("mesh", "meshes"):
        b = io.BytesIO(data)
        b.name = "<pipe>"
        ms = list(read_meshes(b))
        if output == "mesh":
            if len(ms) != 1:
                raise ValueError("expected one mesh from the pipe, got %d" % len(ms))
            return ms[0]
        return ms[0] if len(ms) == 1 else ms
    if output == "table":
        return read_table(io.StringIO(text))
    if output == "bytes":
        return data
    if output == "text":
        return text
    raise ValueError("output: mesh, meshes, table, text, bytes or auto, not %r" % output)


def pipeline(input, *commands, output="auto", check=True, stderr=None):
    """Run commands as a pipeline, input (a Mesh, a list of them, text or
    None) into the first, the last one's output returned: output="auto"
    gives a Mesh (a list for a stream of several), a DataFrame for a table,
    else text; "mesh", "meshes", "table", "text", "bytes" force one.
    A tool that fails raises ToolError (check=False: no raise, and the
    output is what there is).  stderr: a file to pass the tools' messages
    (progress, warnings) to; by default they are collected, and raised."""
    if not commands:
        raise ValueError("pipeline: no command")
    cmds = [[tool_path(str(c[0]))] + [str(a) for a in c[1:]] for c in commands]
    procs, errs = [], []
    prev = subprocess.PIPE
    for i, c in enumerate(cmds):
        p = subprocess.Popen(c, stdin=prev, stdout=subprocess.PIPE,
                             stderr=stderr if stderr is not None else subprocess.PIPE)
        if i > 0:
            procs[-1].stdout.close()   # the next one holds it: SIGPIPE reaches the writer
        procs.append(p)
        prev = p.stdout
    buf = [[] for _ in procs]

    def drain(k):
        buf[k].append(procs[k].stderr.read())

    threads = []
    if stderr is None:
        threads = [threading.Thread(target=drain, args=(k,)) for k in range(len(procs))]
        for t in threads:
            t.start()
    data = _input_bytes(input)

    def feed():
        try:
            procs[0].stdin.write(data)
        except BrokenPipeError:
            pass
        finally:
            try:
                procs[0].stdin.close()
            except BrokenPipeError:
                pass

    w = threading.Thread(target=feed)
    w.start()
    out = procs[-1].stdout.read()
    procs[-1].stdout.close()
    w.join()
    for t in threads:
        t.join()
    for k, p in enumerate(procs):
        p.wait()
        errs.append(b"".join(buf[k]).decode("utf-8", "replace"))
    if check:
        for k, p in enumerate(procs):
            if p.returncode != 0:
                raise ToolError([os.path.basename(cmds[k][0])] + cmds[k][1:], p.returncode,
                                errs[k], out)
    return _output(out, output)


def run(args, input=None, output="auto", check=True, stderr=None):
    """One tool: run(["tis-relax", "--p0", "3.7"], mesh) -> the relaxed
    Mesh.  As pipeline() with one command."""
    if isinstance(args, str):
        args = args.split()
    return pipeline(input, list(args), output=output, check=check, stderr=stderr)
