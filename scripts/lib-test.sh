# Sourced by the scripts/test-*.sh checks, after `tool=NAME`, with the script's arguments:
#   here  the repository;  mrr  the binary ($1, else build/mrr), which must exist;
#   fail REASON  one line "NAME: FAIL: REASON" on stderr, exit 1;
#   skip REASON  one line "NAME: SKIP: REASON", exit 77 (ctest: skipped).
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mrr="${1:-$here/build/mrr}"
fail() { echo "$tool: FAIL: $*" >&2; exit 1; }
skip() { echo "$tool: SKIP: $*" >&2; exit 77; }
[ -x "$mrr" ] || fail "no mrr binary at $mrr"
