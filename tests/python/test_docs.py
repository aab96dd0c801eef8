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
