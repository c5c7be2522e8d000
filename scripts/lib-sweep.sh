# Sourced by the compare-*-sweep.sh scripts (the done-whens "compare passes on every built-in and
# shared scene"): the scenes, and the Markdown table's first two lines.
# shellcheck shell=bash
sweep_scenes=()
for b in demo plane slanted corner steps boxes shadows redwall fence bumpy wires alledges; do sweep_scenes+=("builtin:$b"); done
sweep_scenes+=(arcade apartment cornell)

# sweep_header COLUMN...: "| scene | COLUMN | ... |" and its rule line
sweep_header() {
  local header="| scene |" rule="|---|" column
  for column in "$@"; do
    header+=" $column |"
    rule+="---|"
  done
  echo "$header"
  echo "$rule"
}
