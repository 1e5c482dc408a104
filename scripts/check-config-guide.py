#!/usr/bin/env python3
"""Fails when docs/configuration.md (the hand-written guide) leaves out a key that
semantic-mapper reads. Keys come from `semantic-mapper --print-config`; the guide names a key in
a table row as `| key |`, in a list `| a, key |`, or qualified `| section.key |`.
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


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    binary, guide_path = sys.argv[1:]
    guide = open(guide_path, encoding="utf-8").read()
    missing = [f"[{s}] {k}" for s, k in keys(binary)
               if not re.search(r"(\|\s*|, |\.)" + re.escape(k) + r"(\s*\||,)", guide)]
    if missing:
        print(f"{guide_path} does not describe {len(missing)} key(s) semantic-mapper reads: "
              + ", ".join(missing) + " (add a row; docs/config-reference.md lists them all)")
        return 1
    print(f"{guide_path}: every key semantic-mapper reads is described")
    return 0


if __name__ == "__main__":
    sys.exit(main())
