#!/usr/bin/env python3
"""Fails when docs/configuration.md (the hand-written guide) leaves out a key that
semantic-mapper reads. Keys come from `semantic-mapper --print-config`. The guide names a key
qualified anywhere (`section.key`), or in a table cell (`| key |`, `| a, key |`) under a heading
(## or ###) that names its [section]: `stride` under [points_map] does not cover [orb] stride.
Usage: check-config-guide.py SEMANTIC_MAPPER CONFIGURATION_MD"""
import re
import subprocess
import sys


def keys(binary):
    text = subprocess.run([binary, "--print-config"], check=True, capture_output=True,
                          text=True).stdout
    section, out = "", []
    for raw in text.splitlines():
        line = raw.strip()
        if line.startswith("["):
            section = line[1:line.index("]")]
        elif line and not line.startswith("#") and "=" in line:
            out.append((section, line.split("=", 1)[0].strip()))
    return out


def sections_blocks(guide):
    """{section: text under every heading that names [section]}."""
    out, names, lines = {}, [], []

    def flush():
        for n in names:
            out[n] = out.get(n, "") + "\n".join(lines) + "\n"

    for line in guide.splitlines():
        if line.startswith("## ") or line.startswith("### "):
            flush()
            names, lines = re.findall(r"\[(\w+)\]", line), []
        else:
            lines.append(line)
    flush()
    return out


def described(guide, blocks, section, key):
    k = re.escape(key)
    if re.search(r"\b" + re.escape(section) + r"\." + k + r"\b", guide):
        return True
    return re.search(r"(\|\s*|, )" + k + r"(\s*\||,)", blocks.get(section, "")) is not None


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    binary, guide_path = sys.argv[1:]
    guide = open(guide_path, encoding="utf-8").read()
    blocks = sections_blocks(guide)
    missing = [f"[{s}] {k}" for s, k in keys(binary) if not described(guide, blocks, s, k)]
    if missing:
        print(f"{guide_path} does not describe {len(missing)} key(s) semantic-mapper reads: "
              + ", ".join(missing) + " (add a row; docs/config-reference.md lists them all)")
        return 1
    print(f"{guide_path}: every key semantic-mapper reads is described")
    return 0


if __name__ == "__main__":
    sys.exit(main())
