#!/usr/bin/env bash
# Regenerates the bad-input table in docs/hardening.md from the catalogue itself
# (tests/cli/cli_test.cpp, CliBadInputTest): every case's command, exit status and the one
# line a user sees. Run after adding a case or changing a message.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/build.sh" >/dev/null
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
MRR_BAD_INPUT_LOG="$log" "$here/build/tests/cli_tests" --gtest_filter='Cases/CliBadInputTest.*' --gtest_brief=1 >&2
table="$(mktemp)"
{
  echo "| case | command | exit | what the user sees |"
  echo "|---|---|---|---|"
  cat "$log"
} >"$table"
python3 - "$here/docs/hardening.md" "$table" <<'PY'
import sys
doc, table = sys.argv[1], open(sys.argv[2]).read()
text = open(doc).read()
begin, end = "<!-- bad-inputs:begin -->", "<!-- bad-inputs:end -->"
head, rest = text.split(begin)
_, tail = rest.split(end)
open(doc + ".tmp", "w").write(head + begin + "\n" + table + end + tail)
PY
mv "$here/docs/hardening.md.tmp" "$here/docs/hardening.md"
rm -f "$table"
echo "bad-inputs-doc: $(wc -l <"$log") cases written to docs/hardening.md" >&2
