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


def test_python_example_plots_a_run_against_the_ground_truth(shared, tmp_path):
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[2]
    png = tmp_path / "plot.png"
    out = subprocess.run([sys.executable, str(root / "examples" / "python" / "run_and_plot.py"),
                          str(shared / "data" / "kitti_06_stereo51" / "sequences" / "06"), str(png)],
                         capture_output=True, text=True, env=os.environ)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "tracked 51 of 51 frames" in out.stdout
    assert png.stat().st_size > 10000 and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
