"""The Python example of docs/api.md runs as written (from the repository root, as the page says)."""
import os
import re
from pathlib import Path


def test_api_page_python_example_runs(shared):
    root = Path(__file__).resolve().parents[2]
    page = (root / "docs" / "api.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", page, re.S)
    assert blocks, "docs/api.md has no python example"
    cwd = os.getcwd()
    try:
        os.chdir(root)
        for code in blocks:
            scope = {}
            exec(compile(code, "docs/api.md", "exec"), scope)
    finally:
        os.chdir(cwd)
    assert scope["stats"]["tracked_frames"] >= 70
    assert scope["ape"], "evaluate returned nothing"
    assert len(scope["stamps"]) >= 70
