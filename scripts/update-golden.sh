#!/usr/bin/env bash
# Records the oracle's stage digests for this machine's CPU feature level into
# tests/golden/oracle.json (see tests/oracle/golden_test.cpp). Run it only when a change is
# meant to move the oracle's output, and commit the file with that change.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/build.sh"
MRR_UPDATE_GOLDEN=1 "$here/build/tests/oracle_tests" --gtest_filter='Golden.*'
git -C "$here" diff --stat -- tests/golden/oracle.json
