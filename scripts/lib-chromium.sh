# Sourced by the scripts that load a report in headless Chromium (test-report-browser.sh,
# test-bench-report.sh). Defines: fail, skip, find_chromium (sets $chromium, installing it
# with apt when missing and allowed; skip otherwise) and chromium_flags (offline, headless).
# Expects $tool (the script's name, for messages) and $work (a scratch folder).
fail() { echo "$tool: FAIL: $*" >&2; exit 1; }
skip() { echo "$tool: SKIP: $*" >&2; exit 77; }

find_chromium() {
  chromium="$(command -v chromium || command -v chromium-browser || true)"
  if [ -z "$chromium" ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get > /dev/null; then
      echo "$tool: installing chromium (apt)" >&2
      if ! { DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium > /dev/null 2>&1 ||
             { apt-get update -q > /dev/null 2>&1 &&
               DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium > /dev/null 2>&1; }; }; then
        skip "chromium is missing and apt-get install chromium failed"
      fi
      chromium="$(command -v chromium || true)"
    fi
    [ -n "$chromium" ] || skip "chromium is missing and cannot be installed here (not root or no apt-get)"
  fi
}

chromium_flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
                --disable-component-update --disable-sync --disable-dev-shm-usage --hide-scrollbars
                --enable-logging=stderr --v=0 --virtual-time-budget=5000)

# Console messages Chromium prints for a page (the reports log nothing, so any is a failure).
chromium_console='Uncaught|ERROR:CONSOLE|:CONSOLE[:(]|Failed to load resource|Not allowed to load'
