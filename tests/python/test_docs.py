"""Generated documentation stays in sync with the schemas."""
import os
import runpy

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")


def test_parameter_docs_match_the_schemas():
    gen = runpy.run_path(os.path.join(ROOT, "scripts", "gen_param_docs.py"))
    with open(os.path.join(ROOT, "docs", "parameters.md")) as f:
        committed = f.read()
    assert committed == gen["render"]() + "\n", (
        "docs/parameters.md is stale: PYTHONPATH=build python3 scripts/gen_param_docs.py > docs/parameters.md")


def test_readme_python_example_runs(tmp_path, monkeypatch):
    import re
    import subprocess
    import sys

    with open(os.path.join(ROOT, "README.md")) as f:
        code = re.search(r"```python\n(.*?)```", f.read(), re.S).group(1)
    root = os.path.abspath(ROOT)
    # Run from the repository root, as the README assumes, writing into tmp.
    code = code.replace('"out/top_down.png"', repr(str(tmp_path / "top_down.png")))
    env = dict(os.environ, PYTHONPATH=os.path.abspath(os.environ.get("POINTNPR_BUILD_DIR", "build")))
    subprocess.run([sys.executable, "-c", code], cwd=root, env=env, check=True, timeout=120)
    import numpy as np
    import pointnpr

    image = pointnpr.load_image(str(tmp_path / "top_down.png"))
    # The tile fills the middle of the frame with non-white pixels.
    centre = image[300:420, 500:780, :3]
    assert np.mean(np.all(centre > 0.98, axis=-1)) < 0.05
