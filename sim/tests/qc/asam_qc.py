#!/usr/bin/env python3
"""Runs ASAM's Quality Checker bundles (asam-qc-openscenarioxml, asam-qc-opendrive) on
files and says every issue they find, one line each.

    python asam_qc.py FILE.xosc FILE.xodr ...

Each file goes to its bundle by its extension, with the bundle's checkers all enabled
(minimum level 3, information and up). Exit status 0 when no checker reports an issue and
none ended in error, 1 otherwise, 2 when a bundle is not installed."""

import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

BUNDLES = {
    ".xosc": ("qc_openscenario", "xoscBundle"),
    ".xodr": ("qc_opendrive", "xodrBundle"),
}


def check(path: Path, work: Path) -> list[str]:
    program, bundle = BUNDLES[path.suffix]
    exe = shutil.which(program) or str(Path(sys.executable).parent / program)
    if not Path(exe).exists():
        print(f"{program} is not installed (pip install asam-qc-openscenarioxml asam-qc-opendrive)")
        sys.exit(2)
    result = work / f"{path.name}.xqar"
    config = work / f"{path.name}.config.xml"
    config.write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n<Config>\n'
        f'  <Param name="InputFile" value="{path.resolve()}"/>\n'
        f'  <CheckerBundle application="{bundle}">\n'
        f'    <Param name="resultFile" value="{result}"/>\n'
        "  </CheckerBundle>\n</Config>\n"
    )
    run = subprocess.run([exe, "-c", str(config)], capture_output=True, text=True)
    if run.returncode != 0 or not result.exists():
        return [f"{path}: {program} failed ({run.returncode}): {run.stderr.strip()[-500:]}"]
    problems = []
    checkers = 0
    for checker in ET.parse(result).getroot().iter("Checker"):
        checkers += 1
        name = checker.get("checkerId")
        status = checker.get("status")
        if status == "error":
            problems.append(f"{path}: checker {name} ended in error: {checker.get('summary')}")
        for issue in checker.iter("Issue"):
            where = [
                loc.get("row")
                for loc in issue.iter("FileLocation")
                if loc.get("row") is not None
            ]
            line = f" line {where[0]}" if where else ""
            problems.append(
                f"{path}{line}: {name} ({issue.get('ruleUID')}): {issue.get('description')}"
            )
    print(f"{path}: {checkers} checkers of {bundle} ran")
    return problems


def main() -> int:
    files = [Path(a) for a in sys.argv[1:]]
    problems = []
    with tempfile.TemporaryDirectory() as work:
        for f in files:
            problems += check(f, Path(work))
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
