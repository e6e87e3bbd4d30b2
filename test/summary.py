#!/usr/bin/env python3
"""Print one line summing pytest JUnit XML reports: `N passed, N failed ...`.

`make test` runs pytest twice (see the Makefile); this is its last line.
Usage: python3 test/summary.py REPORT.xml [REPORT.xml ...]; exits 1 if
anything failed or a report is missing.
"""
import sys
import xml.etree.ElementTree as ET


def main(paths):
    total = {'tests': 0, 'failures': 0, 'errors': 0, 'skipped': 0}
    missing = []
    for path in paths:
        try:
            root = ET.parse(path).getroot()
        except (OSError, ET.ParseError):
            missing.append(path)
            continue
        for suite in root.iter('testsuite'):
            for key in total:
                total[key] += int(suite.get(key, 0))
    failed = total['failures'] + total['errors']
    passed = total['tests'] - failed - total['skipped']
    print('%d passed, %d failed, %d skipped%s' % (
        passed, failed, total['skipped'],
        ' (no report from %s)' % ', '.join(missing) if missing else ''))
    return 1 if failed or missing else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
