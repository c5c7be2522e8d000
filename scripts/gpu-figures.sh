#!/usr/bin/env bash
# The GPU run, ready in one command and within one 10-minute device call: `mrr compare` of every
# effect on the shared scenes, `mrr bench` of full and its peers (uniform-1, uniform-2, tiles,
# mrr) on the GL port at 1280x720, 1920x1080 and 3840x2160 with GL_TIME_ELAPSED timer queries
# (the GPU-resident frame: the report's gl object says what each frame read back), mrr's
# passes at 1080p each timed alone (--gpu-timing passes: which draw holds the method back), and
# the paper's sweeps
# that feed Figs. 6 (speedup against samples, at 4K as in the paper), 7 (speedup against
# resolution) and 9 (RMS against resolution), drawn beside the paper's own points
# ($MRR_PAPER_FIGURES, docs/figures.md "The paper's sweeps") by the bench's --report. Everything goes into
# docs/bench/nvidia/ (--out DIR), with a README.md naming the device, the date, every command run
# and each step's wall time; the HTML reports (tens of MB) go to out/gpu-figures-html/ (--html).
#
#   scripts/gpu-figures.sh [--mrr PATH] [--out DIR] [--small] [--steps LIST] [--gl-device N] ...
#   scripts/gpu-figures.sh --help          every option
#
# --small: the same steps at tiny sizes on builtin:demo (and the Cornell box in compare), for
# llvmpipe in CI (ctest gpu_figures_small, through scripts/test-gpu-figures.sh): about a minute.
#
# ---- On the lent NVIDIA machine (the `run` tool; /work/.library/device/README.md) ------------
# build/mrr needs ~260 shared libraries (OpenImageIO pulls in GDAL, ffmpeg, OpenVDB, ...) that a
# bare device machine lacks, and the shared scenes beside the checkout do not travel. So, here,
# once after each build:
#     scripts/gpu-figures.sh --make-bundle
# packs build/mrr, every library it loads (glibc and its loader too, in a folder of their own,
# used only where the device's glibc is older), the glvnd EGL/GL dispatch libraries, the shared
# scenes and the paper's figures into build/gpu-bundle/part1, part2 (xz, ~97 MiB split in parts
# of at most 50 MiB, so that each part plus the working tree stays under the 64 MiB one call
# carries; build/ is ignored, so the parts can be carried). Then three calls, back to back (a
# machine stays warm only 30 s after a call; the parts wait in /tmp/mrr-gpu-bundle on it):
#   1. run(carry=["build/gpu-bundle/part1"], timeout_s=120,
#          command="bash scripts/gpu-figures.sh --bundle build/gpu-bundle")
#      -> "bundle: 1 of 2 parts here", exit 0
#   2. run(carry=["build/gpu-bundle/part2"], timeout_s=600,
#          command="bash scripts/gpu-figures.sh --bundle build/gpu-bundle")
#      -> unpacks, runs the steps until its deadline (540 s after the start, since a command may
#         run 600 s), and after every step refreshes $OUT/nvidia/: README.md, docs.tar.gz (the
#         whole --out folder) and html.tar.gz.NN (as many HTML reports as fit); it ends with
#         "steps left: ..." when the deadline stopped it
#   3. only then: run(timeout_s=600,
#          command="bash scripts/gpu-figures.sh --bundle build/gpu-bundle --steps <the steps left>")
# After each call, here:  mkdir -p docs/bench/nvidia &&
#     tar -xzf <files_at>/nvidia/docs.tar.gz -C docs/bench/nvidia
# and after the last:     scripts/gpu-figures.sh --readme-only   (one README over every call's steps)
# The script sets __EGL_VENDOR_LIBRARY_FILENAMES to the driver's 10_nvidia.json under
# /usr/local/nvidia when that file exists and the variable is unset, and puts the driver's
# library folders on the bundle's library path; mrr takes the first EGL device that gives GL 3.3
# core (--gl-device N picks another). Reports need a python3 with jinja2 and matplotlib: the
# device's `python3` has both (MRR_PYTHON is set to it when /usr/bin/python3 lacks them).
# Estimated device time: ~2 min to start, then every step in call 2: ~7 minutes (the budget
# below: fewer cameras and repeats at the larger sizes, since the H100 runs fragment shaders on 4
# of its SMs). A step that the deadline would cut is not started ("not run: would take ~N s";
# from the last main sweep, scaled by the pixels, cameras and repeats); where one step needs
# more than a whole call, the line names a --cameras that fits. Rerun --make-bundle after every
# build: the device keeps each bundle apart by its sha256.
#
# Exit: 0 when every step ran and passed (or a bundle part was only stashed), 1 when a compare
# failed or a bench exited non-zero (every output is still written), 2 on bad usage or when no
# OpenGL 3.3 context can be made (one line: "gpu-figures: error: ...").
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
tool=gpu-figures
die() { echo "$tool: error: $*" >&2; exit 2; }
log() { echo "[$tool] $*" >&2; }

usage() {
  cat <<EOF
usage: scripts/gpu-figures.sh [options]
  --mrr PATH         the mrr binary (default build/mrr)
  --out DIR          where the figures go (default docs/bench/nvidia; --small: out/gpu-figures-small)
  --html DIR         where the HTML reports go (default out/gpu-figures-html for docs/bench/nvidia,
                     else DIR/html under --out)
  --small            tiny sizes for llvmpipe in CI (160x90, 320x180, 640x360; builtin:demo; 1 camera,
                     1 repeat, 16 samples; --gpu-timing auto)
  --steps LIST       comma-separated: compare, passes, sweeps, main (every size), main-WxH; default all
  --gl-device N      the EGL device index (passed to every mrr command)
  --gpu-timing T     query (default), wall or auto (--small: auto)
  --cameras N        cameras per scene in every main sweep (default: the budget's, 4 at 720p and
                     1080p, 2 at 4K; --small 1)
  --repeats N        timed repeats per setting in every step (default: the budget's, 3 at 720p,
                     2 at 1080p and in the sweeps, 1 at 4K; --small 1)
  --compare-size WxH the size of the compare runs (default 640x360; --small 160x90)
  --deadline S       stop starting work S seconds after the start and skip what would not finish
                     (default 540 where \$OUT is set, as on the device machine; 0: none)
  --dry-run          print the steps and their commands, run nothing
  --readme-only      rewrite README.md from what --out holds (after merging several calls)
  --make-bundle [DIR]  pack mrr, its libraries and the scenes for the device (default build/gpu-bundle)
  --bundle DIR       on the device: stash the parts carried under DIR, unpack when all are there, use them
  -h, --help         this text
EOF
}

# ---- Options ------------------------------------------------------------------------------------
mrr="$here/build/mrr"
out="" html="" small=0 steps_arg="all" gl_device="" timing="" cameras="" repeats="" compare_size=""
deadline="" dry_run=0 readme_only=0 make_bundle="" bundle=""
need() { if [ $# -lt 2 ] || [ -z "$2" ]; then die "$1 needs a value (see --help)"; fi; }
int() { [[ "$2" =~ ^[0-9]+$ ]] || die "$1 $2: expected a whole number"; }
size() { [[ "$2" =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]] || die "$1 $2: expected WIDTHxHEIGHT"; }
args_given=("$@")
while [ $# -gt 0 ]; do
  case "$1" in
    --mrr) need "$@"; mrr="$2"; shift 2 ;;
    --out) need "$@"; out="$2"; shift 2 ;;
    --html) need "$@"; html="$2"; shift 2 ;;
    --small) small=1; shift ;;
    --steps) need "$@"; steps_arg="$2"; shift 2 ;;
    --gl-device) need "$@"; int "$@"; gl_device="$2"; shift 2 ;;
    --gpu-timing) need "$@"; case "$2" in auto|wall|query) timing="$2" ;; *) die "--gpu-timing $2: expected auto, wall or query" ;; esac; shift 2 ;;
    --cameras) need "$@"; int "$@"; [ "$2" -ge 1 ] || die "--cameras must be at least 1"; cameras="$2"; shift 2 ;;
    --repeats) need "$@"; int "$@"; [ "$2" -ge 1 ] || die "--repeats must be at least 1"; repeats="$2"; shift 2 ;;
    --compare-size) need "$@"; size "$@"; compare_size="$2"; shift 2 ;;
    --deadline) need "$@"; int "$@"; deadline="$2"; shift 2 ;;
    --dry-run) dry_run=1; shift ;;
    --readme-only) readme_only=1; shift ;;
    --make-bundle)
      if [ $# -ge 2 ] && [ "${2#-}" = "$2" ]; then make_bundle="$2"; shift 2; else make_bundle="$here/build/gpu-bundle"; shift; fi ;;
    --bundle) need "$@"; bundle="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) die "unknown option $1 (see --help)" ;;
  esac
done
[ -n "$make_bundle" ] && [ -n "$bundle" ] && die "--make-bundle and --bundle do not go together"
command -v python3 > /dev/null || die "python3 is needed (it writes README.md and compare.json)"

# ---- --make-bundle: here, before the device calls -----------------------------------------------
glibc_names='^(ld-linux-x86-64\.so\.2|libc\.so\.6|libm\.so\.6|libmvec\.so\.1|libpthread\.so\.0|libdl\.so\.2|librt\.so\.1|libresolv\.so\.2|libutil\.so\.1|libanl\.so\.1|libnss_files\.so\.2|libnss_dns\.so\.2)$'
if [ -n "$make_bundle" ]; then
  [ -x "$mrr" ] || die "no mrr binary at $mrr (build it first, or give --mrr)"
  for t in ldd xz split sha256sum tar; do command -v "$t" > /dev/null || die "--make-bundle needs $t"; done
  [ "$(uname -m)" = x86_64 ] || die "the device machine is x86-64; this machine is $(uname -m), so build/mrr cannot run there"
  stage="$(mktemp -d)"
  trap 'rm -rf "$stage"' EXIT
  mkdir -p "$stage/b/lib" "$stage/b/glibc" "$stage/b/scenes" "$stage/b/design"
  cp -L "$mrr" "$stage/b/mrr"
  ldd "$mrr" > "$stage/ldd.txt" || die "ldd $mrr failed"
  if grep -q 'not found' "$stage/ldd.txt"; then die "ldd: $(grep -m1 'not found' "$stage/ldd.txt" | xargs)"; fi
  libdir=""
  while read -r lib; do
    name="$(basename "$lib")"
    if [[ "$name" =~ $glibc_names ]]; then cp -L "$lib" "$stage/b/glibc/"; libdir="$(dirname "$(readlink -f "$lib")")"
    else cp -L "$lib" "$stage/b/lib/"; fi
  done < <(awk '$2 == "=>" && $3 ~ /^\// {print $3} $1 ~ /^\/.*ld-linux/ {print $1}' "$stage/ldd.txt")
  # The rest of glibc, for what the driver's libraries load (they must match the loader).
  for name in ld-linux-x86-64.so.2 libc.so.6 libm.so.6 libmvec.so.1 libpthread.so.0 libdl.so.2 librt.so.1 libresolv.so.2 libutil.so.1 libanl.so.1 libnss_files.so.2 libnss_dns.so.2; do
    [ -e "$stage/b/glibc/$name" ] || [ ! -e "$libdir/$name" ] || cp -L "$libdir/$name" "$stage/b/glibc/"
  done
  scenes="${MRR_SCENES_DIR:-$here/../shared/scenes}"
  found=()
  for d in cornell-box dream-apartment sascha-arcade; do
    if [ -d "$scenes/$d" ]; then cp -rL "$scenes/$d" "$stage/b/scenes/"; found+=("$d"); fi
  done
  [ -f "$scenes/README.md" ] && cp "$scenes/README.md" "$stage/b/scenes/"
  paper="${MRR_PAPER_FIGURES:-$scenes/../design/paper-figures.csv}"
  [ -f "$paper" ] && cp "$paper" "$stage/b/design/paper-figures.csv"
  {
    echo "glibc=$(getconf GNU_LIBC_VERSION | awk '{print $2}')"
    echo "made=$(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "commit=$(git -C "$here" rev-parse --short HEAD 2> /dev/null || echo unknown)$(git -C "$here" diff --quiet HEAD 2> /dev/null || echo '+changes')"
    echo "mrr_sha256=$(sha256sum "$mrr" | cut -d' ' -f1)"
    echo "scenes=${found[*]:-none}"
    echo "paper_figures=$([ -f "$stage/b/design/paper-figures.csv" ] && echo yes || echo no)"
  } > "$stage/b/BUNDLE"
  log "packing $(find "$stage/b/lib" -type f | wc -l) libraries, $(find "$stage/b/glibc" -type f | wc -l) of glibc, scenes: ${found[*]:-none} (xz ${XZ_OPT:--6 -T0}; a minute or two)"
  export XZ_OPT="${XZ_OPT:--6 -T0}"
  tar -C "$stage/b" -cf - . | nice -n 10 xz -c > "$stage/bundle.tar.xz"
  sha="$(sha256sum "$stage/bundle.tar.xz" | cut -d' ' -f1)"
  bytes="$(stat -c %s "$stage/bundle.tar.xz")"
  part_mib="${GPU_BUNDLE_PART_MIB:-50}"
  (cd "$stage" && split -b "${part_mib}M" -d -a 2 bundle.tar.xz chunk.)
  rm -rf "$make_bundle"
  n=0
  for c in "$stage"/chunk.*; do n=$((n + 1)); done
  k=0
  for c in "$stage"/chunk.*; do
    k=$((k + 1))
    mkdir -p "$make_bundle/part$k"
    mv "$c" "$make_bundle/part$k/bundle.tar.xz.${c##*.}"
    printf 'parts=%s\nsha256=%s\nbytes=%s\n' "$n" "$sha" "$bytes" > "$make_bundle/part$k/MANIFEST"
  done
  tree_mib=$(( $(git -C "$here" ls-files -z 2> /dev/null | (cd "$here" && xargs -0 stat -c %s 2> /dev/null) | awk '{s += $1} END {print s + 0}') / 1048576 ))
  log "wrote $n parts of $((bytes / 1048576)) MiB in all to $make_bundle (the tracked tree is ~$tree_mib MiB; each call carries at most 64 MiB)"
  rel="${make_bundle#"$here"/}"
  for k in $(seq 1 "$n"); do
    if [ "$k" -lt "$n" ]; then
      echo "call $k: run(carry=[\"$rel/part$k\"], timeout_s=120, command=\"bash scripts/gpu-figures.sh --bundle $rel\")"
    else
      echo "call $k: run(carry=[\"$rel/part$k\"], timeout_s=600, command=\"bash scripts/gpu-figures.sh --bundle $rel\")"
    fi
  done
  exit 0
fi

# ---- The plan -------------------------------------------------------------------------------------
methods=(full uniform-1 uniform-2 tiles mrr)
effects=(ssao ssm ssgi)
if [ "$small" = 1 ]; then
  : "${out:=$here/out/gpu-figures-small}" "${timing:=auto}" "${cameras:=1}" "${repeats:=1}" "${compare_size:=160x90}"
  main_sizes=(160x90 320x180 640x360)
  sweep_size=320x180 resolutions=(160x90 320x180 640x360)
  ssao_sweep=(4 8 16) ssm_sweep=(4 9 16) ssgi_sweep=(4 8 16)
  main_samples=(--samples 16) compare_samples=(--samples 16)
  want_compare=(builtin:demo cornell) want_bench=(builtin:demo)
else
  : "${out:=$here/docs/bench/nvidia}" "${timing:=query}" "${compare_size:=640x360}"
  main_sizes=(1280x720 1920x1080 3840x2160)
  # Fig. 6 was measured at 4K; Figs. 7 and 9 at 720p, 1080p, 1440p and 4K; SSGI's 1088 is a
  # paper's count that the CPU bench leaves out (its 4224 too, which took 60 s at 4K alone here).
  sweep_size=3840x2160 resolutions=(1280x720 1920x1080 2560x1440 3840x2160)
  ssao_sweep=(16 32 64 128 256) ssm_sweep=(100 144 196 256 324) ssgi_sweep=(24 80 288 1088)
  main_samples=() compare_samples=()
  want_compare=(arcade apartment cornell) want_bench=(arcade apartment cornell)
fi
# The budget: every step in one device call of 10 minutes, on an H100 whose fragment shaders run
# on 4 of its SMs. Its last run (docs/bench/nvidia/log, 8 cameras, 3 repeats) took 35 s for
# compare, 249 s for the sweeps (60 of them SSGI-4224 at 4K), and per scene, camera and effect
# 1.25 s of main sweep at 720p, 2.5 s at 1080p and ~11 s at 4K (estimated: it did not fit). A
# setting costs its repeats and a warm-up, so with the cameras and repeats below: compare ~35 s,
# passes ~15 s (estimated: one camera, full and mrr), sweeps ~140 s, main ~45 s at 720p, ~65 s at 1080p, ~100 s at 4K; ~7 minutes with the processes'
# starts and the reports. --cameras and --repeats set every step's.
declare -A step_cameras=() step_repeats=()
if [ "$small" = 0 ]; then
  step_cameras=([1280x720]=4 [1920x1080]=4 [3840x2160]=2)
  step_repeats=([1280x720]=3 [1920x1080]=2 [3840x2160]=1 [sweeps]=2 [passes]=2)
fi
cameras_of() { echo "${cameras:-${step_cameras[$1]:-8}}"; }
repeats_of() { echo "${repeats:-${step_repeats[$1]:-3}}"; }
out="$(realpath -m "$out")"
if [ -z "$html" ]; then
  if [ "$out" = "$here/docs/bench/nvidia" ]; then html="$here/out/gpu-figures-html"; else html="$out/html"; fi
fi
if [ -z "$deadline" ]; then if [ -n "${OUT:-}" ]; then deadline=540; else deadline=0; fi; fi
gl_args=()
[ -n "$gl_device" ] && gl_args=(--gl-device "$gl_device")

all_steps=(compare passes sweeps)
for s in "${main_sizes[@]}"; do all_steps+=("main-$s"); done
selected=()
IFS=',' read -r -a asked <<< "$steps_arg"
for a in "${asked[@]}"; do
  case "$a" in
    all) selected+=("${all_steps[@]}") ;;
    main) for s in "${main_sizes[@]}"; do selected+=("main-$s"); done ;;
    compare|passes|sweeps) selected+=("$a") ;;
    main-*) printf '%s\n' "${all_steps[@]}" | grep -qx -- "$a" || die "--steps: no step $a here (main sizes: ${main_sizes[*]})"; selected+=("$a") ;;
    *) die "--steps: unknown step '$a' (compare, passes, sweeps, main, main-WxH, all)" ;;
  esac
done
# In the canonical order, each once.
plan=()
for s in "${all_steps[@]}"; do printf '%s\n' "${selected[@]}" | grep -qx -- "$s" && plan+=("$s"); done
[ ${#plan[@]} -gt 0 ] || die "--steps $steps_arg selects nothing"
step_index() { local i=0 s; for s in "${all_steps[@]}"; do i=$((i + 1)); if [ "$s" = "$1" ]; then printf '%02d' "$i"; fi; done; }

# ---- README.md from what --out holds ------------------------------------------------------------
write_readme() {
  python3 - "$out" <<'PY'
import glob, json, os, re, sys
out = sys.argv[1]
def kv(path):
    d = {}
    if os.path.exists(path):
        for line in open(path, encoding="utf-8"):
            if "=" in line:
                k, v = line.rstrip("\n").split("=", 1)
                d[k] = v
    return d
dev = kv(os.path.join(out, "log", "device.txt"))
sweeps_md = os.path.join(out, "bench-sweeps.md")
if os.path.exists(sweeps_md):
    dev["paper"] = ("not found (%s): the charts show ours alone" % dev.get("paper")) if "figures were not found" in open(sweeps_md).read() \
        else "drawn beside ours in Figs. 6, 7 and 9 (%s)" % dev.get("paper")
steps = sorted(glob.glob(os.path.join(out, "log", "*.status")))
name = dev.get("gpu_name") or dev.get("renderer") or "unknown device"
L = ["# mrr on %s: the GPU run" % name, ""]
L.append("Made by `scripts/gpu-figures.sh` (%s mode). Regenerate with the commands below; "
         "`scripts/gpu-figures.sh --readme-only --out DIR` rewrites this page from the folder." % dev.get("mode", "?"))
L += ["", "| | |", "|---|---|"]
scripts = []
for s in steps:
    sc = kv(s).get("script")
    if sc and sc not in scripts:
        scripts.append(sc)
if scripts:
    dev["script"] = "; ".join("`%s`" % sc for sc in scripts)
rows = [("GL renderer", dev.get("renderer")), ("GPU (nvidia-smi)", dev.get("gpu_name")), ("driver", dev.get("driver")),
        ("GL timing", dev.get("timing")), ("host", dev.get("host")), ("date (UTC)", dev.get("date")),
        ("commit", dev.get("commit")), ("mrr", dev.get("mrr")), ("script", dev.get("script")),
        ("paper's figures", dev.get("paper")), ("HTML reports", dev.get("html"))]
L += ["| %s | %s |" % (k, v.replace("|", "\\|")) for k, v in rows if v]
L += ["", "## Steps", "", "| step | what | started (UTC) | wall time | status |", "|---|---|---|---|---|"]
commands = []
for s in steps:
    st = kv(s)
    secs = st.get("seconds", "")
    wall = "%.1f s" % float(secs) if secs else "—"
    L.append("| %s | %s | %s | %s | %s |" % (st.get("step", "?"), st.get("what", ""), st.get("started", ""), wall, st.get("status", "?")))
    cmd = s[:-len(".status")] + ".commands"
    if os.path.exists(cmd):
        lines = [l.rstrip("\n") for l in open(cmd, encoding="utf-8") if l.strip()]
        if lines:
            commands.append((st.get("step", "?"), lines))
left = [kv(s).get("step") for s in steps if not kv(s).get("status", "").startswith(("ok", "failed"))]
if left:
    L += ["", "Not run or cut: %s (run them with `--steps %s`)." % (", ".join(left), ",".join(left))]
# The paper's figures beside ours.
figs = sorted(os.path.basename(p) for p in glob.glob(os.path.join(out, "fig[679]-*.png")))
if figs:
    L += ["", "## The paper's Figs. 6, 7 and 9 beside ours", "",
          "Ours solid (measured) and dashed (ideal); the paper's (GTX 1080) in green. "
          "Fig. 6 is speedup against samples, Fig. 7 speedup against resolution, Fig. 9 RMS against resolution "
          "([bench-sweeps.md](bench-sweeps.md), first camera of the first scene).", ""]
    for f in figs:
        L.append("![%s](%s)" % (f[:-4], f))
# The main sweeps.
mains = sorted(glob.glob(os.path.join(out, "bench-main-*.json")),
               key=lambda p: [int(x) for x in re.findall(r"(\d+)x(\d+)", p)[-1]])
if mains:
    L += ["", "## Speed against accuracy, every scene and camera", "",
          "| size | effect | method | measured speedup (median) | ideal (median) | RMS (median) | runs | sanity failures | tables |",
          "|---|---|---|---|---|---|---|---|---|"]
    def med(v):
        v = sorted(x for x in v if x is not None)
        n = len(v)
        return None if not n else (v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2]))
    for p in mains:
        j = json.load(open(p))
        size = re.findall(r"(\d+x\d+)", os.path.basename(p))[-1]
        base = os.path.basename(p)[:-5]
        for e in ("ssao", "ssm", "ssgi"):
            for m in ("full", "uniform-1", "uniform-2", "tiles", "mrr"):
                rs = [r for r in j["runs"] if r["effect"] == e and r["method"] == m and r["group"] == "main" and r["path"] == "gpu"]
                if not rs:
                    continue
                ms, mi, rms = med([r["measured_speedup"] for r in rs]), med([r["ideal_speedup"] for r in rs]), med([r["rms"] for r in rs])
                L.append("| %s | %s-%d | %s | %.2fx | %.2fx | %.3g | %d | %d | [md](%s.md) |" % (
                    size, e, rs[0]["samples"], m, ms, mi, rms if rms is not None else float("nan"), len(rs), len(j["sanity_failures"]), base))
    charts = sorted(os.path.basename(p) for p in glob.glob(os.path.join(out, "main-*-speed-vs-rms-*.png")))
    if charts:
        L.append("")
        for f in charts:
            L.append("![%s](%s)" % (f[:-4], f))
# mrr's passes, each draw timed alone (--gpu-timing passes): where the method's own work goes.
pj = os.path.join(out, "bench-passes.json")
if os.path.exists(pj):
    j = json.load(open(pj))
    L += ["", "## Where mrr's frame goes, pass by pass (`--gpu-timing passes`)", "",
          "Each draw timed alone (glFinish around it), medians of the repeats; read a pass as a share of its "
          "stage (docs/port.md, \"Where a frame's time goes, pass by pass\"). The stages between the G-buffer and "
          "the effect, and the blend, of mrr with the never-slower rule off (`mrr+norule`, so that they run):", "",
          "| effect | size | stage (ms) | passes, costliest first (ms) |", "|---|---|---|---|"]
    for r in j["runs"]:
        if r["method"] != "mrr+norule" or "pass_ms" not in r:
            continue
        for stage in ("edges", "masks", "rule", "blend"):
            ps = sorted(((k.split(" ", 1)[1], v) for k, v in r["pass_ms"].items() if k.split(" ", 1)[0] == stage),
                        key=lambda kv: -kv[1])
            if ps:
                L.append("| %s-%d | %dx%d | %s (%.2f) | %s |" % (r["effect"], r["samples"], r["width"], r["height"], stage,
                         r["stage_ms"].get(stage, 0.0), ", ".join("`%s` %.2f" % kv for kv in ps[:8])))
# The port against the oracle.
cj = os.path.join(out, "compare.json")
if os.path.exists(cj):
    c = json.load(open(cj))
    L += ["", "## The port against the oracle (`mrr compare`)", "",
          "| scene | effect | size | samples | verdict | wall time | output |", "|---|---|---|---|---|---|---|"]
    for r in c:
        L.append("| %s | %s | %s | %s | %s | %.1f s | [txt](%s) |" % (r["scene"], r["effect"], r["size"], r["samples"],
                 r["verdict"], r["seconds"], r["text"]))
if commands:
    L += ["", "## Commands, exactly as run", "",
          "`mrr` stands for %s." % dev.get("mrr_run", "the binary named above"), ""]
    for step, lines in commands:
        L += ["%s:" % step, "", "```sh"] + lines + ["```", ""]
open(os.path.join(out, "README.md"), "w", encoding="utf-8").write("\n".join(L).rstrip("\n") + "\n")
PY
}

if [ "$readme_only" = 1 ]; then
  [ -d "$out/log" ] || die "$out has no log/ folder: nothing to write a README from"
  write_readme
  log "wrote $out/README.md"
  exit 0
fi

# ---- --bundle: on the device, stash the carried parts; unpack once all are there ----------------
mrr_run=() mrr_show="$mrr" mrr_note="$mrr"
if [ -n "$bundle" ]; then
  stash="${MRR_GPU_BUNDLE_STASH:-/tmp/mrr-gpu-bundle}"
  mkdir -p "$stash"
  manifest="$(find "$bundle" -path "$bundle/part*/MANIFEST" 2> /dev/null | sort | head -n1 || true)"
  if [ -n "$manifest" ]; then
    sha="$(sed -n 's/^sha256=//p' "$manifest")" parts="$(sed -n 's/^parts=//p' "$manifest")"
    if [ -z "$sha" ] || [ -z "$parts" ]; then die "$manifest: no parts= or sha256= line"; fi
    mkdir -p "$stash/$sha/parts"
    for f in "$bundle"/part*/bundle.tar.xz.*; do [ -e "$f" ] && cp "$f" "$stash/$sha/parts/"; done
    echo "$sha" > "$stash/current"
  else
    [ -f "$stash/current" ] || die "no bundle: $bundle holds no part*/MANIFEST and none was stashed in $stash (make one with --make-bundle, carry its parts)"
    sha="$(cat "$stash/current")" parts=0
  fi
  root="$stash/$sha/root"
  if [ ! -f "$root/.complete" ]; then
    have=$(find "$stash/$sha/parts" -type f -name "bundle.tar.xz.*" 2> /dev/null | wc -l)
    if [ "$have" -lt "$parts" ] || [ "$parts" = 0 ]; then
      log "bundle: $have of $parts parts here (in $stash/$sha); carry the next part in the next call, while the machine is warm"
      exit 0
    fi
    got="$(cat "$stash/$sha/parts"/bundle.tar.xz.* | sha256sum | cut -d' ' -f1)"
    [ "$got" = "$sha" ] || die "bundle: the $parts parts do not make the bundle (sha256 $got, expected $sha): carry all parts of one --make-bundle"
    log "bundle: unpacking $parts parts into $root"
    rm -rf "$root" && mkdir -p "$root"
    if command -v xz > /dev/null; then unxz=(xz -dc)
    else unxz=(python3 -c 'import lzma, shutil, sys; shutil.copyfileobj(lzma.open(sys.stdin.buffer), sys.stdout.buffer)'); fi
    cat "$stash/$sha/parts"/bundle.tar.xz.* | "${unxz[@]}" | tar -x -C "$root"
    touch "$root/.complete"
  fi
  bglibc="$(sed -n 's/^glibc=//p' "$root/BUNDLE")"
  sglibc="$(getconf GNU_LIBC_VERSION 2> /dev/null | awk '{print $2}' || true)"
  libpath="$root/lib"
  loader=/lib64/ld-linux-x86-64.so.2
  if [ "${MRR_GPU_BUNDLE_LOADER:-}" = bundled ] || [ ! -x "$loader" ] || [ -z "$sglibc" ] ||
     [ "$(printf '%s\n%s\n' "$bglibc" "$sglibc" | sort -V | head -n1)" != "$bglibc" ]; then
    loader="$root/glibc/ld-linux-x86-64.so.2" libpath="$root/lib:$root/glibc"
  fi
  for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do [ -d "$d" ] && libpath="$libpath:$d"; done
  [ -n "${LD_LIBRARY_PATH:-}" ] && libpath="$libpath:$LD_LIBRARY_PATH"
  # The loader named explicitly: mrr finds its libraries, and the python3 it starts for the
  # reports inherits no LD_LIBRARY_PATH.
  mrr="$root/mrr"
  mrr_run=("$loader" --library-path "$libpath" "$mrr")
  mrr_show=mrr
  mrr_note="\`$loader --library-path $libpath $mrr\` (the bundle of $(sed -n 's/^made=//p' "$root/BUNDLE"), commit $(sed -n 's/^commit=//p' "$root/BUNDLE"))"
  [ -n "${MRR_SCENES_DIR:-}" ] || export MRR_SCENES_DIR="$root/scenes"
  [ -n "${MRR_PAPER_FIGURES:-}" ] || export MRR_PAPER_FIGURES="$root/design/paper-figures.csv"
else
  if [ ! -f "$mrr" ] || [ ! -x "$mrr" ]; then die "no mrr binary at $mrr (give --mrr PATH)"; fi
  mrr="$(cd "$(dirname "$mrr")" && pwd)/$(basename "$mrr")"
  mrr_run=("$mrr") mrr_show=mrr mrr_note="\`$mrr\`"
fi
nv_json=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
if [ -f "$nv_json" ] && [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ]; then export __EGL_VENDOR_LIBRARY_FILENAMES="$nv_json"; fi

# ---- Commands, recorded as run ----------------------------------------------------------------------
quote() { local s="" a; for a in "$@"; do s+=" $(printf '%q' "$a")"; done; printf '%s' "${s# }"; }
cmdfile=/dev/null logfile=/dev/null
# run_mrr STDOUT TEE ARGS...: runs mrr within the deadline; stderr to the step's log (and to ours
# when TEE is 1). Returns mrr's exit status, 124 when the deadline cut it.
run_mrr() {
  local stdout="$1" tee="$2" rc limit=()
  shift 2
  if [ "$dry_run" = 1 ]; then echo "$mrr_show $(quote "$@")"; return 0; fi
  echo "$mrr_show $(quote "$@")" >> "$cmdfile"
  if [ "$deadline" -gt 0 ]; then
    local left=$((deadline - SECONDS))
    [ "$left" -gt 5 ] || return 124
    limit=(timeout --kill-after=10 "$left")
  fi
  set +e
  if [ "$tee" = 1 ]; then
    "${limit[@]}" "${mrr_run[@]}" "$@" 2>&1 > "$stdout" | tee -a "$logfile" >&2
    rc=${PIPESTATUS[0]}
  else
    "${limit[@]}" "${mrr_run[@]}" "$@" > "$stdout" 2>> "$logfile"
    rc=$?
  fi
  set -e
  [ "$rc" -eq 137 ] && rc=124
  return "$rc"
}

# ---- Reports need python3 with jinja2 and matplotlib ------------------------------------------
report_python=""
if [ -z "${MRR_PYTHON:-}" ]; then
  for p in /usr/bin/python3 "$(command -v python3)"; do
    if [ -x "$p" ] && "$p" -c 'import jinja2, matplotlib' 2> /dev/null; then report_python="$p"; break; fi
  done
  [ -n "$report_python" ] && [ "$report_python" != /usr/bin/python3 ] && export MRR_PYTHON="$report_python"
elif "$MRR_PYTHON" -c 'import jinja2, matplotlib' 2> /dev/null; then
  report_python="$MRR_PYTHON"
fi

# ---- A GL context, and the scenes ---------------------------------------------------------------
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
renderer="(dry run)"
if [ "$dry_run" = 0 ]; then
  if ! "${mrr_run[@]}" render --path gpu --scene builtin:plane --size 8x8 --samples 1 -q "${gl_args[@]}" \
       --report "$work/gl.json" > /dev/null 2> "$work/gl.err"; then
    die "no OpenGL 3.3 context: $(grep -m1 . "$work/gl.err" || echo "mrr render --path gpu failed")"
  fi
  renderer="$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["renderer"])' "$work/gl.json")"
  if [ "$small" = 0 ] && [[ "$renderer" =~ llvmpipe|softpipe|swrast|SwiftShader ]]; then
    die "the GL renderer is $renderer, a software one: the full run is for a GPU (hours here); use --small (on the device: is the NVIDIA EGL vendor found? see __EGL_VENDOR_LIBRARY_FILENAMES in the header)"
  fi
fi
missing=" "
for s in $(printf '%s\n' "${want_compare[@]}" "${want_bench[@]}" | sort -u); do
  if [[ "$s" != builtin:* ]] && [ -x "$mrr" ] && ! "${mrr_run[@]}" info "$s" > /dev/null 2> "$work/info.err"; then
    log "skipping scene $s: $(grep -m1 'error' "$work/info.err" || echo 'mrr info failed')"
    missing+="$s "
  fi
done
present() { local s; for s in "$@"; do [[ "$missing" == *" $s "* ]] || echo "$s"; done; }  # the scenes mrr can open
mapfile -t compare_scenes < <(present "${want_compare[@]}")
mapfile -t bench_scenes < <(present "${want_bench[@]}")
[ ${#bench_scenes[@]} -gt 0 ] || { log "none of ${want_bench[*]} is here: the benches run builtin:demo"; bench_scenes=(builtin:demo); }
[ ${#compare_scenes[@]} -gt 0 ] || { log "none of ${want_compare[*]} is here: compare runs builtin:demo"; compare_scenes=(builtin:demo); }

bench_common=(bench --paths gpu "${gl_args[@]}" --gpu-timing "$timing" --methods "${methods[@]}" --effects "${effects[@]}"
              --frames 0 --no-stress --no-fovea)
report_for() { rep=(); if [ -n "$report_python" ]; then rep=(--report "$html/$1"); fi; }  # sets rep
since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }'; }

# ---- Device facts, for the README ---------------------------------------------------------------
if [ "$dry_run" = 0 ]; then
  mkdir -p "$out/log" "$html" || die "cannot make $out/log and $html"
  gpu_name="" driver=""
  if command -v nvidia-smi > /dev/null; then
    gpu_name="$(nvidia-smi --query-gpu=name --format=csv,noheader 2> /dev/null | head -n1 || true)"
    driver="$(nvidia-smi --query-gpu=driver_version --format=csv,noheader 2> /dev/null | head -n1 || true)"
  fi
  commit="$(git -C "$here" rev-parse --short HEAD 2> /dev/null || true)"
  if [ -n "$commit" ] && ! git -C "$here" diff --quiet HEAD 2> /dev/null; then commit+="+changes"; fi
  [ -n "$bundle" ] && commit="$(sed -n 's/^commit=//p' "$root/BUNDLE")"
  paper="${MRR_PAPER_FIGURES:-the shared design folder beside the scenes}"
  {
    echo "renderer=$renderer"
    echo "gpu_name=$gpu_name"
    echo "driver=$driver"
    echo "timing=--gpu-timing $timing"
    echo "host=$(grep -m1 '^model name' /proc/cpuinfo 2> /dev/null | cut -d: -f2- | sed 's/^ //'), $(nproc) threads, $(uname -sr)"
    echo "date=$(date -u '+%Y-%m-%d %H:%M')"
    echo "commit=${commit:-unknown}"
    echo "mode=$([ "$small" = 1 ] && echo small || echo full)"
    echo "script=scripts/gpu-figures.sh $(quote "${args_given[@]}")"
    echo "mrr=$mrr"
    echo "mrr_run=$mrr_note"
    echo "paper=$paper"
    echo "html=$([ -n "$report_python" ] && echo "$html" || echo "none: no python3 with jinja2 and matplotlib, so no charts")"
  } > "$out/log/device.txt"
fi

# ---- $OUT/nvidia on the device machine: at most 8 files come back, so tarballs ------------------
export_out() {  # export_out [html]
  [ -n "${OUT:-}" ] && [ -d "$OUT" ] && [ "$dry_run" = 0 ] || return 0
  mkdir -p "$OUT/nvidia"
  cp "$out/README.md" "$OUT/nvidia/README.md" 2> /dev/null || true
  local ex=()
  case "$html/" in "$out"/*) ex=(--exclude="./${html#"$out"/}") ;; esac
  tar -C "$out" "${ex[@]}" -czf "$OUT/nvidia/docs.tar.gz.tmp" . && mv "$OUT/nvidia/docs.tar.gz.tmp" "$OUT/nvidia/docs.tar.gz"
  [ "${1:-}" = html ] || return 0
  # The HTML reports, most wanted first, as many as fit in 4 files of 15 MiB.
  local d total=0 sz keep=() order=()
  rm -f "$OUT/nvidia"/html.tar.gz.*
  for d in "$html"/compare-* "$html/bench-sweeps" "$html"/bench-main-*; do [ -d "$d" ] && order+=("$d"); done
  for d in "${order[@]}"; do
    sz=$(du -sb "$d" | cut -f1)
    if [ $((total + sz)) -le $((58 * 1048576)) ]; then keep+=("${d#"$html"/}"); total=$((total + sz)); fi
  done
  [ ${#keep[@]} -gt 0 ] || return 0
  tar -C "$html" -czf - "${keep[@]}" | split -b 15M -d -a 2 - "$OUT/nvidia/html.tar.gz."
  log "\$OUT/nvidia: README.md, docs.tar.gz and html.tar.gz.* (${#keep[@]} of ${#order[@]} reports: cat html.tar.gz.* | tar -xz)"
}

# ---- The steps ----------------------------------------------------------------------------------
step_what() {
  case "$1" in
    compare) echo "mrr compare, ${effects[*]} on ${compare_scenes[*]} at $compare_size" ;;
    passes) echo "mrr's passes (--gpu-timing passes): full and mrr (the rule off, so that its passes run) at ${main_sizes[1]}, ${effects[*]}, ${bench_scenes[0]}, 1 camera" ;;
    sweeps) echo "Figs. 6, 7, 9: samples sweep at $sweep_size, resolution sweep ${resolutions[*]} on ${bench_scenes[0]}" ;;
    main-*) echo "bench main sweep at ${1#main-}: ${bench_scenes[*]}, $(cameras_of "${1#main-}") cameras, $(repeats_of "${1#main-}") repeats, ${methods[*]}" ;;
  esac
}
failed=0
step_compare() {
  local scene effect name rc t0 samples status=ok bad=0
  mkdir -p "$out/compare"
  : > "$work/compare.tsv"
  for scene in "${compare_scenes[@]}"; do
    for effect in "${effects[@]}"; do
      name="${scene//:/-}-$effect"
      t0=$(date +%s.%N)
      rc=0
      report_for "compare-$name"
      run_mrr "$out/compare/$name.txt" 0 compare --scene "$scene" --effect "$effect" --size "$compare_size" \
        "${compare_samples[@]}" "${gl_args[@]}" -q "${rep[@]}" || rc=$?
      if [ ${#compare_samples[@]} -gt 0 ]; then samples="${compare_samples[1]}"
      else case "$effect" in ssao) samples=64 ;; ssm) samples=196 ;; ssgi) samples=288 ;; esac; fi
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$scene" "$effect" "$compare_size" "$samples" "$rc" \
        "$(since "$t0")" "compare/$name.txt" >> "$work/compare.tsv"
      log "  compare $scene $effect: $(tail -n1 "$out/compare/$name.txt" 2> /dev/null || echo "exit $rc")"
      if [ "$rc" = 124 ]; then status="cut at the deadline"; break 2; fi
      [ "$rc" = 0 ] || { bad=$((bad + 1)); status="failed ($bad of $((${#compare_scenes[@]} * ${#effects[@]})))"; failed=1; }
    done
  done
  python3 - "$work/compare.tsv" "$out" <<'PY'
import json, os, sys
rows = []
for line in open(sys.argv[1]):
    scene, effect, size, samples, rc, secs, text = line.rstrip("\n").split("\t")
    body = open(os.path.join(sys.argv[2], text)).read().strip().splitlines() if os.path.exists(os.path.join(sys.argv[2], text)) else []
    last = body[-1] if body else ""
    verdict = "PASS" if rc == "0" and last.startswith("PASS") else ("cut at the deadline" if rc == "124" else
              (last if last.startswith("FAIL") else "error (exit %s)" % rc))
    rows.append({"scene": scene, "effect": effect, "size": size, "samples": int(samples), "exit": int(rc),
                 "verdict": verdict, "pass": verdict == "PASS", "seconds": round(float(secs), 2), "text": text})
json.dump(rows, open(os.path.join(sys.argv[2], "compare.json"), "w"), indent=1)
PY
  step_status="$status"
}
step_bench() {  # step_bench NAME ARGS...: one bench, its tables, and its charts copied beside them
  local name="$1" rc=0
  shift
  report_for "bench-$name"
  run_mrr /dev/null 1 "${bench_common[@]}" "$@" --json "$out/bench-$name.json" --csv "$out/bench-$name.csv" \
    --markdown "$out/bench-$name.md" "${rep[@]}" || rc=$?
  if [ "$rc" = 124 ]; then step_status="cut at the deadline"; return; fi
  if [ "$rc" != 0 ]; then step_status="failed (mrr bench exited $rc)"; failed=1; return; fi
  step_status=ok
  local c
  for c in "$html/bench-$name/charts"/*.png; do
    [ -e "$c" ] || continue
    case "$name" in
      sweeps) case "$(basename "$c")" in fig*) cp "$c" "$out/" ;; esac ;;
      *) cp "$c" "$out/$name-$(basename "$c")" ;;
    esac
  done
}
step_passes() {  # each draw timed alone (docs/port.md, "Where a frame's time goes"): pass_ms in the JSON
  local rc=0
  run_mrr /dev/null 1 bench --paths gpu "${gl_args[@]}" --gpu-timing passes --methods full mrr+norule --effects "${effects[@]}" \
    --frames 0 --no-stress --no-fovea --no-sweeps --scenes "${bench_scenes[0]}" --cameras 1 --repeats "$(repeats_of passes)" \
    --sizes "${main_sizes[1]}" "${main_samples[@]}" --json "$out/bench-passes.json" --markdown "$out/bench-passes.md" || rc=$?
  if [ "$rc" = 124 ]; then step_status="cut at the deadline"; return; fi
  if [ "$rc" != 0 ]; then step_status="failed (mrr bench exited $rc)"; failed=1; return; fi
  step_status=ok
}
step_sweeps() {
  step_bench sweeps --scenes "${bench_scenes[0]}" --cameras 1 --repeats "$(repeats_of sweeps)" --sizes "${main_sizes[0]}" "${main_samples[@]}" \
    --sweep-size "$sweep_size" --resolutions "${resolutions[@]}" \
    --ssao-sweep "${ssao_sweep[@]}" --ssm-sweep "${ssm_sweep[@]}" --ssgi-sweep "${ssgi_sweep[@]}"
}
step_main() {
  step_bench "main-$1" --scenes "${bench_scenes[@]}" --cameras "$(cameras_of "$1")" --repeats "$(repeats_of "$1")" --sizes "$1" \
    "${main_samples[@]}" --no-sweeps
}

n=${#plan[@]} k=0 last_px=0 last_s=0 left_steps=()
log "$n steps into $out ($([ "$small" = 1 ] && echo small || echo full) mode; renderer: $renderer; --gpu-timing $timing$([ "$deadline" -gt 0 ] && echo "; deadline ${deadline} s"))"
for step in "${plan[@]}"; do
  k=$((k + 1))
  idx="$(step_index "$step")"
  what="$(step_what "$step")"
  cmdfile="$out/log/$idx-$step.commands" logfile="$out/log/$idx-$step.log"
  if [ "$dry_run" = 1 ]; then
    echo "step $k/$n: $step: $what"
    case "$step" in
      compare) for s in "${compare_scenes[@]}"; do for e in "${effects[@]}"; do
          report_for "compare-${s//:/-}-$e"
          run_mrr /dev/null 0 compare --scene "$s" --effect "$e" --size "$compare_size" "${compare_samples[@]}" "${gl_args[@]}" -q "${rep[@]}"
        done; done ;;
      passes) step_passes ;;
      sweeps) step_sweeps ;;
      main-*) step_main "${step#main-}" ;;
    esac
    continue
  fi
  started="$(date -u '+%Y-%m-%d %H:%M:%S')"
  # Skip a main sweep that the deadline would cut: it scales with the pixels and with its cameras
  # times (repeats + the warm-up), from the last one.
  px=0
  if [[ "$step" == main-* ]]; then
    wh="${step#main-}"
    px=$(( ${wh%x*} * ${wh#*x} * $(cameras_of "$wh") * ($(repeats_of "$wh") + 1) ))
  fi
  step_status="" seconds=""
  if [ "$deadline" -gt 0 ] && [ $((deadline - SECONDS)) -le 15 ]; then
    step_status="not run: the deadline (${deadline} s) had passed"
  elif [ "$deadline" -gt 0 ] && [ "$px" -gt 0 ] && [ "$last_px" -gt 0 ] &&
       [ "$(python3 -c "print(int($last_s * $px / $last_px))")" -gt $((deadline - SECONDS)) ]; then
    est=$(python3 -c "print(int($last_s * $px / $last_px))")
    step_status="not run: would take ~$est s, $((deadline - SECONDS)) s left"
    if [ "$est" -gt $((deadline - 60)) ]; then  # more than a whole call: fewer cameras
      cams="$(cameras_of "${step#main-}")"
      step_status+=" (more than one call: try --cameras $(( cams * (deadline - 60) / est > 0 ? cams * (deadline - 60) / est : 1 )))"
    fi
  fi
  if [ -n "$step_status" ]; then
    log "step $k/$n: $step: $step_status"
  else
    log "step $k/$n: $what"
    : > "$cmdfile"
    : > "$logfile"
    t0=$(date +%s.%N)
    case "$step" in
      compare) step_compare ;;
      passes) step_passes ;;
      sweeps) step_sweeps ;;
      main-*) step_main "${step#main-}" ;;
    esac
    seconds="$(since "$t0")"
    if [ "$px" -gt 0 ] && [ "$step_status" = ok ]; then last_px=$px last_s=${seconds%.*}; fi
    log "step $k/$n: $step: $step_status in ${seconds} s"
  fi
  case "$step_status" in ok|failed*) ;; *) left_steps+=("$step") ;; esac
  printf 'step=%s\nwhat=%s\nstarted=%s\nseconds=%s\nstatus=%s\nscript=%s\n' "$step" "$what" "$started" "$seconds" "$step_status" \
    "scripts/gpu-figures.sh $(quote "${args_given[@]}")" > "$out/log/$idx-$step.status"
  write_readme
  export_out
done
[ "$dry_run" = 1 ] && exit 0
export_out html
log "wrote $out (README.md$([ -n "$report_python" ] && echo "; HTML reports in $html"))"
if [ ${#left_steps[@]} -gt 0 ]; then
  steps_left="$(IFS=,; echo "${left_steps[*]}")"
  log "steps left: $steps_left (run again with --steps $steps_left)"
fi
exit "$failed"
