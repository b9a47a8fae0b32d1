"""Which packages a fresh interpreter loads for given imports: the boundary tests' one helper."""

from __future__ import annotations

import json
import subprocess
import sys


def packages_loaded(imports: str, packages: set[str], run: str = "") -> list[str]:
    """Sorted modules of `packages` in sys.modules after `import <imports>` (and `run`, its output
    discarded) in a new process."""
    code = "\n".join([
        "import contextlib, io, json, sys",
        f"import {imports}",
        "with contextlib.redirect_stdout(io.StringIO()):",
        f"    {run or 'pass'}",
        f"print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in {sorted(packages)!r})))",
    ])
    output = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(output.stdout)
