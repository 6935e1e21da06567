"""Every module of the package imports on its own, first, in a fresh process.

An import cycle fails only when the cycle is entered at a particular module
(``import ppm_stiffness.maps.loaded`` raised ImportError in a fresh interpreter while
``import ppm_stiffness.maps.batch`` worked; issue 19, item 11), so each module must be
the first of the package to be imported in its own process. One child interpreter
imports the third-party libraries the package uses (none of which imports the package)
and then forks once per module: each fork imports one module with no module of the
package loaded, in about 0.1 s (a new interpreter per module would cost numpy's import
each time). Where ``os.fork`` does not exist, each module gets its own interpreter.
"""

from __future__ import annotations

import json
import subprocess
import sys

_CHILD = r"""
import importlib, importlib.util, json, os, pathlib, sys, traceback

for name in ("numpy", "pydantic", "rich", "rich.table", "tomllib", "scipy", "scipy.linalg",
             "matplotlib", "matplotlib.pyplot"):
    try:
        importlib.import_module(name)
    except ImportError:
        pass  # optional: the module that needs it is then imported cold too
assert not any(m.split(".")[0] == "ppm_stiffness" for m in sys.modules)

root = pathlib.Path(importlib.util.find_spec("ppm_stiffness").submodule_search_locations[0])
names = []
for path in sorted(root.rglob("*.py")):
    parts = path.relative_to(root.parent).with_suffix("").parts
    if parts[-1] == "__init__":
        parts = parts[:-1]
    if parts[-1] != "__main__":  # runs the CLI on import, by design
        names.append(".".join(parts))

failures = {}


def start(name):
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: import one module, report, leave without cleanup
        os.close(read)
        try:
            importlib.import_module(name)
            message = b""
        except BaseException:
            message = traceback.format_exc(limit=1).encode()
        os.write(write, message[-2000:])
        os._exit(1 if message else 0)
    os.close(write)
    return pid, read


def finish(name, pid, read):
    with os.fdopen(read, "rb") as fh:
        text = fh.read().decode()
    _, status = os.waitpid(pid, 0)
    if status != 0:
        failures[name] = text.strip().splitlines()[-1] if text.strip() else f"status {status}"


if hasattr(os, "fork"):
    running = []
    for name in names:  # a few children at a time
        running.append((name, *start(name)))
        if len(running) >= 2 * (os.cpu_count() or 1):
            finish(*running.pop(0))
    for job in running:
        finish(*job)
else:
    for name in names:
        run = __import__("subprocess").run(
            [sys.executable, "-c", f"import {name}"], capture_output=True, text=True
        )
        if run.returncode:
            failures[name] = run.stderr.strip().splitlines()[-1]
print(json.dumps({"modules": names, "failures": failures}))
"""


def test_every_module_imports_first_in_a_fresh_process() -> None:
    run = subprocess.run(
        [sys.executable, "-c", _CHILD], capture_output=True, text=True, check=True, timeout=300
    )
    result = json.loads(run.stdout)
    assert "ppm_stiffness.maps.loaded" in result["modules"]
    assert "ppm_stiffness.legs.types._ppr_reduced" in result["modules"]
    assert len(result["modules"]) > 60
    assert result["failures"] == {}
