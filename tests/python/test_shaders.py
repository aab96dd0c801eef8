"""Every shader, in every pass variant, compiles under glslang's strict GLSL
4.50 front end. Mesa accepts some non-standard GLSL that GPU drivers refuse
(e.g. a non-constant `const` initializer); this catches it on a machine
without a GPU, including the 64-bit-atomics variant llvmpipe cannot run."""
import os
import re
import subprocess

import pytest

SHADERS = os.path.join(os.path.dirname(__file__), "..", "..", "shaders")
INCLUDE = re.compile(r'^\s*#include\s+"([^"]+)"\s*$')


def expand(name, seen=None):
    # The same include rule as cpp/gl/shaders.cpp: each file once.
    seen = set() if seen is None else seen
    if name in seen:
        return ""
    seen.add(name)
    out = []
    with open(os.path.join(SHADERS, name)) as f:
        for line in f:
            m = INCLUDE.match(line)
            out.append(expand(m.group(1), seen) + "\n" if m else line)
    return "".join(out)


def variants(name):
    text = expand(name)
    # A shader may list its variants: "// variants: A B | C | ..." (defines per variant; N=V defines N as V).
    declared = re.search(r"^// variants: (.+)$", text, re.M)
    if declared:
        return [v.split() for v in declared.group(1).split("|")]
    passes = sorted(set(re.findall(r"\b(PASS_[A-Z0-9_]+)\b", text)))
    sets = [[p] for p in passes] or [[]]
    if "INT64_ATOMICS" in text:
        sets += [["INT64_ATOMICS"] + s for s in sets]
    return sets


STAGES = {".comp", ".vert", ".frag"}
CASES = [(f, tuple(d)) for f in sorted(os.listdir(SHADERS)) if os.path.splitext(f)[1] in STAGES
         for d in variants(f)]


def test_every_stage_file_is_covered():
    assert any(f == "points.comp" and "INT64_ATOMICS" in d for f, d in CASES)
    assert len({f for f, _ in CASES}) >= 12


@pytest.mark.parametrize("name,defines", CASES, ids=[f"{f}[{','.join(d)}]" for f, d in CASES])
def test_shader_compiles_with_strict_glsl(tmp_path, name, defines):
    src = "#version 450 core\n" + "".join(f"#define {d.replace('=', ' ')}\n" for d in defines) + expand(name)
    path = tmp_path / ("shader" + os.path.splitext(name)[1])
    path.write_text(src)
    r = subprocess.run(["glslangValidator", str(path)], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
