"""The core must not drag in the user-interface stack."""

import json
import subprocess
import sys


def test_import_jointid_loads_no_ui_packages():
    code = (
        "import json, sys; import jointid, jointid.experiment, jointid.report, jointid.cli; "
        "print(json.dumps(sorted(m for m in sys.modules "
        "if m.split('.')[0] in {'textual', 'plotext', 'rich', 'tui', 'textual_plotext'})))"
    )
    output = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(output.stdout) == []
