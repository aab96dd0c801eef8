"""The package refers to itself only relatively: as a Blender extension or
a legacy add-on unpacked under another folder name it is not `pointnpr`
(bl_ext.<repository>.pointnpr, pointnpr-main), and an absolute
`import pointnpr` would fail or pick up another copy."""
import ast
import glob
import os
import shutil
import subprocess
import sys
import textwrap

from conftest import BUILD_DIR

SOURCES = os.path.join(os.path.dirname(__file__), "..", "..", "python_addon", "pointnpr")


def test_no_absolute_import_of_the_package_inside_it():
    offenders = []
    for path in glob.glob(os.path.join(SOURCES, "**", "*.py"), recursive=True):
        with open(path) as f:
            tree = ast.parse(f.read(), path)
        for node in ast.walk(tree):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else []
            if isinstance(node, ast.ImportFrom) and node.level == 0:
                names = [node.module or ""]
            if any(n == "pointnpr" or n.startswith("pointnpr.") for n in names):
                offenders.append("%s:%d" % (os.path.relpath(path, SOURCES), node.lineno))
    assert offenders == []


def test_the_package_works_under_another_name(tmp_path):
    shutil.copytree(os.path.join(BUILD_DIR, "pointnpr"), str(tmp_path / "renamed_npr"))
    script = textwrap.dedent("""
        import sys
        import renamed_npr, renamed_npr.presets
        style = renamed_npr.presets.style(next(iter(renamed_npr.presets.PRESETS)))
        assert isinstance(style, renamed_npr.Style)
        assert "pointnpr" not in sys.modules, sorted(m for m in sys.modules if "npr" in m)
        print("RENAMED_OK")
    """)
    out = subprocess.run([sys.executable, "-c", script], cwd=str(tmp_path), capture_output=True, text=True,
                         env=dict(os.environ, PYTHONPATH=str(tmp_path)))
    assert out.returncode == 0 and "RENAMED_OK" in out.stdout, out.stderr[-3000:]
