#!/usr/bin/python3
"""No tracked file speaks of the project's history in work periods (the word for one, then a number).

Code, config, docs and file names describe the software and its measurements; the pattern below
is assembled from two parts so that this file does not match it itself. The check also runs the
pattern on a planted line, so that a broken pattern cannot pass unnoticed.
"""
import os
import re
import subprocess
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
PATTERN = re.compile("[Ss]" + r"ession[-_ ]?[0-9]")


def tracked_files():
    try:
        out = subprocess.run(["git", "-C", ROOT, "ls-files", "-z"], check=True, capture_output=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        sys.exit(f"test_no_history_words: cannot list the tracked files with git in {ROOT}: {e}")
    return [p for p in out.decode().split("\0") if p]


def main():
    planted = "measured in s" + "ession 7"
    if not PATTERN.search(planted) or PATTERN.search("sessions of the tracker"):
        sys.exit("test_no_history_words: the pattern does not behave as intended")
    files = tracked_files()
    if len(files) < 100:
        sys.exit(f"test_no_history_words: only {len(files)} tracked files found under {ROOT}")
    hits = []
    for path in files:
        if PATTERN.search(path):
            hits.append(f"{path}: file name")
        full = os.path.join(ROOT, path)
        if not os.path.isfile(full):
            continue
        with open(full, "rb") as f:
            data = f.read()
        if b"\0" in data[:8192]:
            continue  # binary (images, weights)
        for number, line in enumerate(data.decode("utf-8", errors="replace").splitlines(), 1):
            if PATTERN.search(line):
                hits.append(f"{path}:{number}: {line.strip()[:120]}")
    if hits:
        print(f"{len(hits)} history reference(s) in tracked files:")
        print("\n".join(hits[:50]))
        sys.exit(1)
    print(f"no history references in {len(files)} tracked files")


if __name__ == "__main__":
    main()
