"""Copy the held-out samples (samples.py) out of a git directory of glTF-Sample-Assets into SAMPLES_DIR, as
NAME/VARIANT/files and NAME/README.md; a file the snapshot lacks (the fetch tool leaves out files of 4 MiB and
more) is reported and skipped.

Usage: python docs/runs/2026-11-27-heldout-khronos/extract.py GIT_DIR SAMPLES_DIR
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from samples import SAMPLES  # noqa: E402


def git(git_dir: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["git", f"--git-dir={git_dir}", *args], capture_output=True)


def main(git_dir: str, out: Path) -> int:
    missing = 0
    for sample in SAMPLES:
        listing = git(git_dir, "ls-tree", "-r", "HEAD", f"Models/{sample.name}/{sample.variant}",
                      f"Models/{sample.name}/README.md").stdout.decode()
        for line in listing.splitlines():
            meta, path = line.split("\t", 1)
            blob = git(git_dir, "cat-file", "blob", meta.split()[2])
            if blob.returncode:
                print(f"missing from the snapshot: {path}")
                missing += 1
                continue
            target = out / path.removeprefix("Models/")
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(blob.stdout)
    print(f"{len(SAMPLES)} samples, {missing} file(s) missing")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1], Path(sys.argv[2])))
