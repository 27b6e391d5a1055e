#!/usr/bin/env python3
"""Writes a long paste for timing `vkpath check` (issue 58): the workshop's helpers once
(tests/solutions/programs/exercise7_tab.glsl without its mainImage), then COUNT distinct
small helper functions that no workshop function calls, about 150 bytes each, as a notes
file that grew by pasting (14 000 helpers: about 2 MB).

    python3 scripts/make_long_paste.py 14000 > /tmp/long_paste.glsl
    /usr/bin/time -v vkpath check /tmp/long_paste.glsl
"""
import os
import sys

count = int(sys.argv[1]) if len(sys.argv) > 1 else 14000
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
with open(os.path.join(root, "tests/solutions/programs/exercise7_tab.glsl")) as tab:
    text = tab.read()
# The functions without the entry point (and what follows it).
text = text[: text.index("void mainImage")]
out = [text]
for i in range(count):
    out.append(
        f"vec3 shade_term_{i}(vec3 normal, vec3 light, float k) {{\n"
        f"    float lit = max(dot(normal, light), 0.0) * k;\n"
        f"    return vec3(lit * {1.0 + i % 97 / 100:.2f}, lit, lit * {i % 13}.0);\n"
        f"}}\n"
    )
sys.stdout.write("".join(out))
