#!/usr/bin/env python3
"""Writes a long paste for timing `vkpath check` (issue 58): the workshop's helpers once
(tests/solutions/programs/exercise7_tab.glsl without its mainImage), then COUNT distinct
small helper functions that no workshop function calls, about 150 bytes each, as a notes
file that grew by pasting (14 000 helpers: about 2 MB). With "loops", each helper has a loop
bounded by a parameter (which check guards), about 180 bytes each.

    python3 scripts/make_long_paste.py 14000 > /tmp/long_paste.glsl
    python3 scripts/make_long_paste.py 12000 loops > /tmp/long_paste_loops.glsl
    /usr/bin/time -v vkpath check /tmp/long_paste.glsl
"""
import os
import sys

count = int(sys.argv[1]) if len(sys.argv) > 1 else 14000
loops = len(sys.argv) > 2 and sys.argv[2] == "loops"
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
with open(os.path.join(root, "tests/solutions/programs/exercise7_tab.glsl")) as tab:
    text = tab.read()
# The functions without the entry point (and what follows it).
text = text[: text.index("void mainImage")]
out = [text]
for i in range(count):
    if loops:
        out.append(
            f"float accumulate_{i}(float x, int n) {{\n"
            f"    float sum = 0.0;\n"
            f"    for (int k = 0; k < n; ++k) {{\n"
            f"        sum += sin(x * float(k) + {i % 101}.0);\n"
            f"    }}\n"
            f"    return sum;\n"
            f"}}\n"
        )
        continue
    out.append(
        f"vec3 shade_term_{i}(vec3 normal, vec3 light, float k) {{\n"
        f"    float lit = max(dot(normal, light), 0.0) * k;\n"
        f"    return vec3(lit * {1.0 + i % 97 / 100:.2f}, lit, lit * {i % 13}.0);\n"
        f"}}\n"
    )
sys.stdout.write("".join(out))
