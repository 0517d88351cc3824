"""docs/python.md's code blocks run as written, in order, in an empty folder."""

import os
import pathlib
import re
import subprocess
import sys

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "python.md"


def test_python_md_example_runs(tmp_path):
    text = DOC.read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 3
    script = tmp_path / "example.py"
    script.write_text("\n".join(blocks))
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                          text=True, env=dict(os.environ, MPLBACKEND="Agg"))
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "carotid-map.png").stat().st_size > 10000
    assert (tmp_path / "carotid-flat.vtp").stat().st_size > 10000
    assert "vessel.FlatMap" in done.stdout
    # The shell line of "Install" too.
    line = re.search(r'```sh\n(python3 -c .*?)\n```', text).group(1)
    shell = subprocess.run(line.replace("python3", sys.executable, 1), shell=True, cwd=tmp_path,
                           capture_output=True, text=True)
    assert shell.returncode == 0 and "vessel.FlatMap" in shell.stdout, shell.stderr
