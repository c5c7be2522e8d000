// mrr — command line. Subcommands: render, probe, bench (see README "Command line").
#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <malloc.h>

#include <algorithm>
#include <cctype>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/byo.h"
#include "app/diff.h"
#include "app/frame_file.h"
#include "app/frame_options.h"
#include "app/info.h"
#include "app/options.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/memory.h"
#include "common/pixel_memory.h"
#include "compare/bench.h"
#include "compare/html_report.h"
#include "compare/against.h"
#include "compare/parity.h"
#include "compare/probe_both.h"
#include "compare/report_python.h"
#include "compare/report.h"
#include "compare/rule.h"
#include "cpu_ref/probe.h"
#include "explore/server.h"
#include "gpu/pipeline.h"
#include "scenes/builtin.h"
#include "scenes/catalog.h"

namespace mrr {
namespace {

// Checks that `path` ends in one of `extensions` (any case) and can be written, before any
// work starts.
void checkOutput(const std::string& path, const std::string& option, const std::vector<std::string>& extensions) {
  std::string lower = path;
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  bool ok = false;
  std::string list;
  for (const std::string& e : extensions) {
    ok = ok || (lower.size() > e.size() && lower.compare(lower.size() - e.size(), e.size(), e) == 0);
    list += (list.empty() ? "" : " or ") + e;
  }
  require(ok, option + " " + path + ": expected a " + list + " file");
  checkOutputLocation(path, option);
}

// Two options naming one file would silently overwrite each other.
void requireDistinct(const std::vector<std::pair<std::string, std::string>>& outputs) {
  for (size_t i = 0; i < outputs.size(); ++i)
    for (size_t j = i + 1; j < outputs.size(); ++j)
      require(outputs[i].second.empty() || outputs[i].second != outputs[j].second,
              outputs[i].first + " and " + outputs[j].first + " name the same file " + outputs[i].second);
}

ProgressFn progressPrinter(bool quiet, const std::string& what) {
  if (quiet) return {};
  return [what](const std::string& stage) { std::cerr << "[mrr] " << what << ": " << stage << "\n"; };
}

int threadCount(int requested) {
  return requested > 0 ? requested : tbb::this_task_arena::max_concurrency();
}

// `--report DIR` of compare and bench: the folder is made, parents too, as `mkdir -p` would.
// What cannot be made is left to checkOutputLocation, which names the reason.
void makeReportDir(const std::string& dir) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) std::filesystem::create_directories(dir, ec);
}

// A frame as command-line options, quoted for a POSIX shell where needed.
std::string frameCommandLine(const nlohmann::json& frame) {
  std::string line;
  for (const std::string& w : frameArgs(frame, "frame")) {
    const bool plain = w.find_first_of(" '\"$`\\*?[]{}()<>|&;!#~") == std::string::npos;
    std::string quoted = plain ? w : "'" + w + "'";
    line += (line.empty() ? "" : " ") + quoted;
  }
  return line;
}

// `mrr compare`: the oracle and the port on the same frame, every stage compared (SPEC §8).
// Exit 0 when every stage is within tolerance, 1 when one is not, 2 on bad input.
// With `against` (issue 17): the oracle against another renderer's stages (compare/against.h);
// the port does not run.
int runCompare(FrameOptions& fo, const std::string& reportDir, const std::string& against) {
  fo.checkPath();
  if (!against.empty()) checkForeignStagesFile(against, fo.effect);
  fo.neverSlowerDefault = false;
  std::vector<std::string> effects = {fo.effect};
  if (fo.effect == "all") effects = {"ssao", "ssm", "ssgi"};
  std::vector<Settings> settings;
  for (const std::string& e : effects) {
    FrameOptions one = fo;
    one.effect = e;
    settings.push_back(one.settings());
  }
  require(fo.threads >= 0 && fo.threads <= 1024, "--threads: must be in [0, 1024]");
  if (!reportDir.empty()) {
    requireReportPython();  // before the folder is made: a missing package writes nothing
    makeReportDir(reportDir);
    checkOutputLocation((std::filesystem::path(reportDir) / "index.html").string(), "--report");
  }
  int64_t memory = 0;
  for (const Settings& s : settings) memory = std::max(memory, 2 * estimateFrameBytes(makeConstants(s, 1.0f), true));
  requireMemory(memory, memoryLimit(fo.memoryLimitGiB), "comparing a " + fo.size + " frame on both paths");

  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<size_t>(threadCount(fo.threads)));
  if (!fo.quiet) std::cerr << "[mrr] loading " << fo.scene << "\n";
  const ResolvedScene rs = resolveScene(fo.sceneRequest());
  const Renderer cpu(rs.scene);
  std::unique_ptr<gpu::GpuRenderer> port;
  if (against.empty()) port = std::make_unique<gpu::GpuRenderer>(rs.scene, fo.glDevice, gpu::parseGpuTiming(fo.gpuTiming));
  const std::string portName = port ? port->renderer() : against;
  if (!fo.quiet && port) std::cerr << "[mrr] GL renderer: " << port->renderer() << "\n";
  bool pass = true;
  // Frames are kept for the HTML report (two frames with every stage per effect).
  std::vector<std::unique_ptr<FrameResult>> kept;
  std::vector<ComparedFrame> compared;
  const CostModel costs = fo.costModel("cpu");
  for (const Settings& s : settings) {
    const Constants k = makeConstants(s, rs.scene.bounds().diagonal());
    auto oracle =
        std::make_unique<FrameResult>(cpu.render(rs.camera, k, {true, progressPrinter(fo.quiet, "oracle"), &costs}));
    std::unique_ptr<FrameResult> ported;
    ParityResult result;
    std::string notChecked;
    if (port) {
      ported = std::make_unique<FrameResult>(port->render(rs.camera, k, {true, progressPrinter(fo.quiet, "port"), &costs}));
      result = compareFrames(*oracle, *ported, rs.scene.light);
    } else {
      ForeignStages foreign = readForeignStages(against, *oracle);
      for (const std::string& n : foreign.ignored)
        std::cerr << "mrr: warning: --against " << against << ": part " << n << " names no stage; not checked\n";
      result = compareForeign(*oracle, foreign, rs.scene.light);
      notChecked = formatNotChecked(foreign);
      ported = std::make_unique<FrameResult>(std::move(foreign.frame));
    }
    if (&s != &settings.front()) std::cout << "\n";  // the last line is the verdict
    std::cout << "== compare " << rs.scene.name << ", " << toString(s.effect) << ", " << toString(s.mode) << ", "
              << s.width << "x" << s.height << ", " << k.samples() << " samples; oracle (cpu_ref) vs "
              << (port ? "port (" + port->renderer() + ")" : against) << "\n"
              << notChecked << formatParityTable(result, port ? "the port's" : "the file's");
    pass = pass && result.pass();
    if (!reportDir.empty()) {
      std::string probe = "mrr probe --path both " + (against.empty() ? "" : "--against " + against + " ") +
                          frameCommandLine(fo.frame(rs, s));
      compared.push_back({toString(s.effect), oracle.get(), ported.get(), std::move(result), probe});
      kept.push_back(std::move(oracle));
      kept.push_back(std::move(ported));
    }
  }
  if (!reportDir.empty()) {
    // The command that reproduces the frame exactly: the camera and light as resolved.
    nlohmann::json frame = fo.frame(rs, settings.front());
    if (effects.size() > 1) {  // one command for every effect, each at its own sample count unless given
      frame["effect"] = "all";
      if (!fo.samples) frame.erase("samples");
    }
    std::string command = "mrr compare " + frameCommandLine(frame);
    const std::string label = fo.scene == rs.scene.name
                                  ? rs.scene.name
                                  : fo.scene + " (" + std::filesystem::path(rs.scene.name).filename().string() + ")";
    if (!against.empty()) command += " --against " + against;
    CompareReportInfo info{label, rs.scene.credit, portName, command};
    if (!against.empty()) info.subject = against + " (another renderer's stages)";
    writeCompareReport(reportDir, info, compared);
    if (!fo.quiet) std::cerr << "[mrr] wrote " << (std::filesystem::path(reportDir) / "index.html").string() << "\n";
  }
  return pass ? 0 : 1;
}

// Levenshtein distance, for "did you mean" on a mistyped option.
size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// CLI11's parse errors as mrr's one line (MrrError: "mrr: error: ...", exit 2), the same as
// every other bad input; CLI11 words them for a terminal and exits 100+.
// The closest of `known` to `word`: at most two edits, and fewer than half its length.
std::string closest(const std::string& word, const std::vector<std::string>& known) {
  std::string best;
  size_t bestDistance = 3;
  for (const std::string& k : known) {
    const size_t d = editDistance(word, k);
    if (d < bestDistance && 2 * d < k.size()) {
      best = k;
      bestDistance = d;
    }
  }
  return best;
}

// `first`: the first argument, when there is one (a mistyped command lands there).
MrrError usageError(const CLI::App& app, const CLI::ParseError& e, const std::string& first) {
  // The subcommand given, if the parse got that far: its options are the ones meant.
  const std::vector<const CLI::App*> given = app.get_subcommands([](const CLI::App*) { return true; });
  const CLI::App* sub = nullptr;
  for (const CLI::App* s : given)
    if (s->parsed()) sub = s;
  const std::string where = sub ? sub->get_name() + ": " : "";
  const std::string what = e.what();
  if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
    std::vector<std::string> known;
    for (const CLI::App* s : sub ? std::vector<const CLI::App*>{sub} : given)
      for (const CLI::Option* o : s->get_options())
        for (const std::string& n : o->get_lnames()) known.push_back("--" + n);
    std::string unknown, positional;
    std::istringstream words(what.substr(what.find(':') + 1));
    for (std::string w; words >> w;) {
      if (w.rfind("-", 0) == 0) unknown = w.substr(0, w.find('='));  // CLI11 lists them last to first
      else positional = w;
    }
    if (unknown.empty()) return MrrError(where + "unexpected argument " + positional + " (mrr --help lists the commands and options)");
    const std::string best = closest(unknown, known);
    return MrrError(where + "unknown option " + unknown + (best.empty() ? "" : " (did you mean " + best + "?)"));
  }
  if (dynamic_cast<const CLI::RequiredError*>(&e) && !sub) {
    std::vector<std::string> commands;
    std::string list;  // "render, probe, ... or bench"
    for (const CLI::App* s : given) commands.push_back(s->get_name());
    for (size_t i = 0; i < commands.size(); ++i)
      list += (i == 0 ? "" : i + 1 == commands.size() ? " or " : ", ") + commands[i];
    if (first.empty() || first[0] == '-') return MrrError("a command is required: " + list + " (mrr --help)");
    const std::string best = closest(first, commands);
    return MrrError("unknown command " + first + (best.empty() ? " (expected " + list + ")" : " (did you mean " + best + "?)"));
  }
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) && what.find(" required ") != std::string::npos &&
      what.find(" missing") != std::string::npos) {
    // "--size: 1 required TEXT missing": the option came last, without its value.
    return MrrError(where + what.substr(0, what.find(':')) + ": needs a value");
  }
  if (dynamic_cast<const CLI::ConversionError*>(&e)) {
    // "Could not convert: --samples = abc": say what the option takes.
    const size_t colon = what.find(": "), equals = what.find(" = ");
    if (colon != std::string::npos && equals != std::string::npos && equals > colon) {
      const std::string name = what.substr(colon + 2, equals - colon - 2);
      const std::string value = what.substr(equals + 3);
      const CLI::Option* option = sub ? sub->get_option_no_throw(name) : nullptr;
      const std::string type = option ? option->get_type_name() : "";
      const std::string expected = type == "INT" || type == "UINT" ? "a whole number" : type == "FLOAT" ? "a number" : "";
      return MrrError(name + " " + value + ": " + (expected.empty() ? "not a valid value" : "expected " + expected));
    }
  }
  return MrrError(where + what);
}

int run(int argc, char** argv) {
  CLI::App app{"mrr: multi-resolution rendering of expensive screen-space lighting (Besenthal et al.): "
               "the CPU oracle (cpu_ref/, --path cpu) and the OpenGL 3.3 port (gpu/, --path gpu)"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "help for every subcommand");

  FrameOptions renderOpts;
  std::string out, shaded, stages, report, frameOut;
  bool reference = false;
  auto* render = app.add_subcommand("render", "render one frame and write the effect buffer, stages and report");
  renderOpts.add(*render);
  render->add_option("--out", out, "final effect buffer: .exr (float) or .png (preview)");
  render->add_option("--shaded", shaded, "shaded image for viewing: .exr (linear) or .png (sRGB)");
  render->add_option("--stages", stages, "every stage as a multi-part .exr");
  render->add_option("--report", report, "JSON report: levels, shaded pixels, ideal speedup, timings");
  render->add_option("--frame-out", frameOut,
                     "the frame as a frame file (JSON): --frame reads it back and renders the same bits");
  render->add_flag("--reference", reference, "also render mode full and add error_vs_full to the report");

  FrameOptions probeOpts;
  std::string pixel;
  bool json = false;
  auto* probe = app.add_subcommand("probe", "follow one full-res pixel through every stage");
  probeOpts.add(*probe);
  probe->add_option("--pixel", pixel, "X,Y of the full-res pixel")->required();
  probe->add_flag("--json", json, "print JSON instead of text");

  FrameOptions compareOpts;
  std::string compareReportDir;
  auto* compare = app.add_subcommand("compare", "run the oracle and the GL port on one frame and compare every stage");
  compareOpts.add(*compare);
  compare->add_option("--report", compareReportDir, "also write a self-contained HTML report into this folder");
  std::string againstFile;
  for (CLI::App* c : {compare, probe}) addAgainstOption(*c, againstFile);

  explore::ServerOptions exploreOpts;
  exploreOpts.frame.size = "320x180";  // re-renders in well under a second (docs/explore.md)
  exploreOpts.frame.samples = 16;
  auto* explore = app.add_subcommand(
      "explore", "serve a local page on one frame: every stage as a layer, oracle beside port, probes, live knobs");
  exploreOpts.frame.add(*explore);
  explore->add_option("--port", exploreOpts.port, "TCP port to serve on (0: any free one; the URL is printed)")
      ->capture_default_str();
  explore->add_option("--host", exploreOpts.host,
                      "address to listen on (default 127.0.0.1: this machine only; 0.0.0.0 opens it to the network)")
      ->capture_default_str();
  SceneRequest infoRequest;
  std::string infoSize = "1280x720", infoBlend = "opaque";
  std::optional<float> infoFov;
  bool infoJson = false, infoFlip = false, infoNoFlip = false;
  auto* infoCmd = app.add_subcommand(
      "info", "what a scene holds: bounds, triangles, cameras, light, extensions, materials, and a suggested view");
  infoCmd->add_option("scene", infoRequest.scene, "builtin:NAME, a shared scene (cornell, arcade, apartment) or a .gltf/.glb path")
      ->required();
  infoCmd->add_option("--size", infoSize, "WxH of the image the suggested view is fitted to")->capture_default_str();
  infoCmd->add_option("--fov", infoFov, "vertical field of view, degrees");
  infoCmd->add_flag("--flip-up", infoFlip, "rotate the scene 180 degrees about X (files authored Y-down)");
  infoCmd->add_flag("--no-flip-up", infoNoFlip, "do not flip, even where the scene catalogue would");
  infoCmd->add_option("--blend-materials", infoBlend, "opaque or skip, as render takes it")->capture_default_str();
  infoCmd->add_flag("--json", infoJson, "print JSON instead of text");

  BenchOptions benchOpts;
  std::vector<std::string> benchSizes, benchResolutions, benchPaths = {"cpu"};
  std::string benchSweepSize, benchStabilitySize, benchStressSize, calibrateOut, ruleSweepOut, ruleReplayIn,
      ruleCostModelFile;
  bool quick = false, noSweeps = false, noStress = false;
  int glDevice = -1;
  std::string benchGpuTiming = "auto";
  auto* bench = app.add_subcommand(
      "bench", "speed against accuracy: every method against full, side by side; charts, stability, stress scenes");
  bench->add_option("--paths", benchPaths, "cpu (the oracle) and/or gpu (the port)")->capture_default_str();
  bench->add_option("--gl-device", glDevice, "gpu: the EGL device index");
  bench->add_option("--gpu-timing", benchGpuTiming, "gpu: auto, wall or query (as render's --gpu-timing)")
      ->capture_default_str();
  bench->add_option("--scenes", benchOpts.scenes, "scenes of the main sweep")->capture_default_str();
  bench->add_option("--sizes", benchSizes, "sizes WxH of the main sweep (default 1280x720)");
  bench->add_option("--effects", benchOpts.effects, "effects: ssao ssm ssgi")->capture_default_str();
  bench->add_option("--samples", benchOpts.samples,
                    "sample counts of the main sweep (default: the paper's middle count, ssao 64, ssm 196, ssgi 288)");
  bench->add_option("--methods", benchOpts.methods, "methods: full uniform-1 uniform-2 tiles mrr")->capture_default_str();
  bench->add_option("--cameras", benchOpts.cameras, "cameras per scene (the paper: 8)")->capture_default_str();
  bench->add_option("--repeats", benchOpts.repeats, "timed repeats per configuration")->capture_default_str();
  bench->add_option("--threads", benchOpts.threads, "the oracle's threads (0 = all cores)");
  bench->add_flag("--no-sweeps", noSweeps, "skip the paper's sweeps (samples, resolution)");
  bench->add_option("--sweep-size", benchSweepSize, "size of the samples sweep (default 1280x720)");
  bench->add_option("--ssao-sweep", benchOpts.ssaoSweep, "SSAO sample counts of the samples sweep")->capture_default_str();
  bench->add_option("--ssm-sweep", benchOpts.ssmSweep, "SSM sample counts of the samples sweep")->capture_default_str();
  bench->add_option("--ssgi-sweep", benchOpts.ssgiSweep,
                    "SSGI sample counts of the samples sweep (the paper's 1088 and 4224 take minutes per setting here)")
      ->capture_default_str();
  bench->add_option("--resolutions", benchResolutions, "sizes of the resolution sweep (default 1280x720 1920x1080)");
  bench->add_option("--frames", benchOpts.frames, "frames per camera path (0: no stability runs)")->capture_default_str();
  bench->add_option("--stability-size", benchStabilitySize, "size of the camera-path frames (default 320x180)");
  bench->add_option("--stability-scenes", benchOpts.stabilityScenes, "scenes of the camera paths")->capture_default_str();
  bench->add_option("--stability-effects", benchOpts.stabilityEffects, "effects of the camera paths")
      ->capture_default_str();
  bench->add_option("--stress-scenes", benchOpts.stressScenes, "stress scenes")->capture_default_str();
  bench->add_flag("--no-stress", noStress, "skip the stress scenes");
  bench->add_option("--stress-size", benchStressSize, "size of the stress runs (default 1280x720)");
  bench->add_option("--json", benchOpts.jsonOut, "write every figure as JSON");
  bench->add_option("--csv", benchOpts.csvOut, "write every run as CSV");
  bench->add_option("--markdown", benchOpts.markdownOut, "write the tables as Markdown");
  bench->add_option("--report", benchOpts.reportDir, "write an HTML page with the charts, tables and images into DIR");
  bench->add_flag("--check", benchOpts.check, "exit 1 when a sanity check fails");
  bench->add_option("--calibrate", calibrateOut,
                    "measure the never-slower rule's costs on each --paths path and write them as JSON (FILE, "
                    "or FILE with {path} replaced)");
  bench->add_option("--cold", benchOpts.coldRuns,
                    "also render each main-sweep frame as a user does, in this many fresh `mrr render` processes per "
                    "method (full and mrr, alternating), and report their speedup beside the warm one")
      ->check(CLI::Range(0, 100));
  bench->add_option("--rule-sweep", ruleSweepOut,
                    "check the never-slower rule on frames nobody tuned it to (shared, built-in and stress scenes; "
                    "catalogue, default, sky and close-up views; 320x180 to 1920x1080) and write them as JSON "
                    "(scripts/rule-chart.py draws it)");
  bench->add_option("--rule-replay", ruleReplayIn,
                    "re-decide every frame of a --rule-sweep JSON with this build's built-in cost models, from the "
                    "counts it recorded, and judge them by the times it measured (renders nothing)");
  bench->add_option("--cost-model", ruleCostModelFile,
                    "with --rule-sweep or --rule-replay: the rule's costs, a JSON written by --calibrate ({path} is "
                    "replaced by cpu or gpu; default: built in)");
  bench->add_flag("--quick", quick,
                  "minutes on 2 cores: builtin:demo and the arcade at 320x180, 2 cameras, 3 repeats, small sweeps, "
                  "8-frame paths at 96x54, stress scenes at 160x90");

  // Issue 17: the user's own shaders on every command that runs the port, and `mrr shaders`.
  std::string shaderDir;
  for (CLI::App* c : {render, probe, compare, bench}) addShadersOption(*c, shaderDir);
  ShadersCommand shadersCommand;
  addShadersCommand(app, shadersCommand);
  DiffOptions diffOptions;  // issue 36: `mrr diff REF TEST` (app/diff.h)
  addDiffCommand(app, diffOptions);

  // --frame F.json stands for the options it holds (app/frame_file.h), inserted before the
  // command line's own, which win.
  std::vector<std::string> words(argv + 1, argv + argc);
  words = expandFrameFile(words);
  try {
    std::vector<std::string> reversed(words.rbegin(), words.rend());  // CLI11 takes them last to first
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --help-all
    throw usageError(app, e, words.empty() ? "" : words.front());
  }

  if (shadersCommand.command->parsed()) return runShadersCommand(shadersCommand);
  if (diffOptions.command->parsed()) return runDiff(diffOptions);
  if (!shaderDir.empty()) {
    const FrameOptions& f = *render ? renderOpts : *probe ? probeOpts : compareOpts;
    const bool port = *compare || (*bench && std::count(benchPaths.begin(), benchPaths.end(), "gpu") > 0) ||
                      ((*render || *probe) && f.path != "cpu");
    require(port, "--shaders " + shaderDir + ": the shaders are the port's; run it with --path gpu" +
                      (*bench ? std::string(" (bench: --paths gpu)") : *probe ? " or both" : ""));
    useShaderDirectory(shaderDir);
  }

  if (*bench) {
    if (quick) {  // defaults for a run of minutes; options given explicitly still win
      if (!bench->count("--scenes")) benchOpts.scenes = {"builtin:demo", "arcade"};
      if (!bench->count("--sizes")) benchOpts.sizes = {{320, 180}};
      if (!bench->count("--samples")) benchOpts.samples = {16};
      if (!bench->count("--cameras")) benchOpts.cameras = 2;
      // three repeats: the median of one is too noisy for --check on a loaded 2-core machine
      if (!bench->count("--repeats")) benchOpts.repeats = 3;
      if (!bench->count("--sweep-size")) benchOpts.sweepSize = {160, 90};
      if (!bench->count("--resolutions")) benchOpts.resolutions = {{96, 54}, {160, 90}};
      if (!bench->count("--ssao-sweep")) benchOpts.ssaoSweep = {8, 16};
      if (!bench->count("--ssm-sweep")) benchOpts.ssmSweep = {16, 36};
      if (!bench->count("--ssgi-sweep")) benchOpts.ssgiSweep = {8, 16};
      if (!bench->count("--frames")) benchOpts.frames = 8;
      if (!bench->count("--stability-size")) benchOpts.stabilitySize = {96, 54};
      if (!bench->count("--stability-scenes")) benchOpts.stabilityScenes = {"builtin:demo"};
      if (!bench->count("--stress-size")) benchOpts.stressSize = {160, 90};
    }
    if (!benchSizes.empty()) {
      benchOpts.sizes.clear();
      for (const auto& s : benchSizes) benchOpts.sizes.push_back(parseSize(s));
    }
    if (!benchResolutions.empty()) {
      benchOpts.resolutions.clear();
      for (const auto& s : benchResolutions) benchOpts.resolutions.push_back(parseSize(s));
    }
    if (!benchSweepSize.empty()) benchOpts.sweepSize = parseSize(benchSweepSize);
    if (!benchStabilitySize.empty()) benchOpts.stabilitySize = parseSize(benchStabilitySize);
    if (!benchStressSize.empty()) benchOpts.stressSize = parseSize(benchStressSize);
    benchOpts.paperSweeps = !noSweeps;
    if (noStress) benchOpts.stressScenes.clear();
    require(benchOpts.repeats >= 1 && benchOpts.repeats <= 100, "--repeats: must be in [1, 100]");
    require(benchOpts.cameras >= 1 && benchOpts.cameras <= 64, "--cameras: must be in [1, 64]");
    require(benchOpts.frames == 0 || (benchOpts.frames >= 2 && benchOpts.frames <= 10000),
            "--frames: must be 0 or in [2, 10000]");
    std::vector<std::pair<int, int>> allSizes = benchOpts.sizes;
    allSizes.insert(allSizes.end(), benchOpts.resolutions.begin(), benchOpts.resolutions.end());
    for (const auto& sz : {benchOpts.sweepSize, benchOpts.stabilitySize, benchOpts.stressSize}) allSizes.push_back(sz);
    for (const auto& [w, h] : allSizes)
      require(w >= 1 && h >= 1 && w <= kMaxImageSize && h <= kMaxImageSize,
              "--sizes " + std::to_string(w) + "x" + std::to_string(h) + ": each side must be in [1, " +
                  std::to_string(kMaxImageSize) + "]");
    for (const std::string& m : benchOpts.methods) parseMode(m);  // validates the name
    for (const std::string& e : benchOpts.stabilityEffects) parseEffect(e);  // validates the name
    // Every sample count in its effect's range: the main sweep's for each chosen effect, and
    // each effect's samples sweep.
    auto validateCounts = [](Effect effect, const std::vector<int>& counts) {
      Settings probeSettings = defaultSettings(effect);
      for (int n : counts) {
        probeSettings.setSamples(n);
        validateSettings(probeSettings);
      }
    };
    for (const std::string& e : benchOpts.effects) validateCounts(parseEffect(e), benchOpts.samples);
    validateCounts(Effect::Ssao, benchOpts.ssaoSweep);
    validateCounts(Effect::Ssm, benchOpts.ssmSweep);
    validateCounts(Effect::Ssgi, benchOpts.ssgiSweep);
    for (const std::string& p : benchPaths)
      require(p == "cpu" || p == "gpu", "--paths " + p + ": unknown path (expected cpu or gpu)");
    require(benchOpts.threads >= 0 && benchOpts.threads <= 1024, "--threads: must be in [0, 1024]");
    if (!benchOpts.jsonOut.empty()) checkOutput(benchOpts.jsonOut, "--json", {".json"});
    if (!benchOpts.markdownOut.empty()) checkOutput(benchOpts.markdownOut, "--markdown", {".md"});
    if (!benchOpts.csvOut.empty()) checkOutput(benchOpts.csvOut, "--csv", {".csv"});
    if (!benchOpts.reportDir.empty()) {
      requireReportPython();  // before the folder is made: a missing package writes nothing
      makeReportDir(benchOpts.reportDir);
    }
    if (!benchOpts.reportDir.empty())
      checkOutputLocation((std::filesystem::path(benchOpts.reportDir) / "index.html").string(), "--report");
    requireDistinct({{"--json", benchOpts.jsonOut}, {"--markdown", benchOpts.markdownOut}, {"--csv", benchOpts.csvOut}});
    require(ruleCostModelFile.empty() || !ruleSweepOut.empty() || !ruleReplayIn.empty(),
            "--cost-model: only with --rule-sweep or --rule-replay (the bench's methods run with the built-in rule)");
    if (!ruleReplayIn.empty())  // no path, no GL
      return replayRuleSweep(ruleReplayIn, ruleCostModelFile, benchOpts.jsonOut, std::cout);
    // The paths, each behind a RenderFn; the GL context is made once and shared by every scene.
    const int threads = threadCount(benchOpts.threads);
    std::vector<BenchPath> paths;
    for (const std::string& p : benchPaths) {
      if (p == "cpu") {
        paths.push_back({"cpu", "cpu_ref (oracle), " + std::to_string(threads) + " threads on " + cpuModelName(),
                         [](const Scene& scene) -> RenderFn {
                           auto r = std::make_shared<Renderer>(scene);
                           return [r](const Camera& c, const Constants& k, const RenderOptions& o) { return r->render(c, k, o); };
                         }});
      } else {
        // Probe the context up front, so a missing EGL device is one line before any work.
        const gpu::GpuTiming timing = gpu::parseGpuTiming(benchGpuTiming);
        const std::string renderer = gpu::GlContext(glDevice).renderer();
        paths.push_back({"gpu",
                         "OpenGL 3.3 port on " + renderer + " (GPU-resident frame; " +
                             (gpu::usesTimerQueries(timing, renderer) ? "GL_TIME_ELAPSED per stage" : "glFinish + wall clock per stage") + ")",
                         [glDevice, timing](const Scene& scene) -> RenderFn {
                           auto r = std::make_shared<gpu::GpuRenderer>(scene, glDevice, timing);
                           return [r](const Camera& c, const Constants& k, const RenderOptions& o) { return r->render(c, k, o); };
                         }});
      }
    }
    if (!calibrateOut.empty()) {
      for (const BenchPath& p : paths) {
        const std::string file = withPathName(calibrateOut, p.name);
        checkOutput(file, "--calibrate", {".json"});
        const CostModel model = calibrateCostModel(p, benchOpts.repeats, threads);
        writeTextFile(file, model.toJson().dump(2) + "\n");
        std::cout << p.name << ": " << model.toJson().dump() << "\n";
      }
      return 0;
    }
    if (!ruleSweepOut.empty()) {
      checkOutput(ruleSweepOut, "--rule-sweep", {".json"});
      RuleSweepOptions ro;
      ro.jsonOut = ruleSweepOut;
      ro.repeats = benchOpts.repeats;
      ro.threads = threads;
      ro.costModelFile = ruleCostModelFile;
      for (const BenchPath& p : paths) ruleCostModel(ro.costModelFile, p.name);  // a bad file fails before the sweep
      if (bench->count("--scenes")) ro.scenes = benchOpts.scenes;
      const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
      ro.machine = benchOpts.machine.empty() ? cpuModelName() + ", " + std::to_string(hw) + " hardware threads" : benchOpts.machine;
      return runRuleSweep(ro, paths, std::cout);
    }
    return runBench(benchOpts, paths, std::cout);
  }

  if (*compare) return runCompare(compareOpts, compareReportDir, againstFile);
  if (*explore) return explore::serve(exploreOpts);

  if (*infoCmd) {
    const auto [w, h] = parseSize(infoSize);
    require(w >= 1 && h >= 1 && w <= 16384 && h <= 16384, "--size " + infoSize + ": each side must be in [1, 16384]");
    infoRequest.aspect = static_cast<float>(w) / static_cast<float>(h);
    infoRequest.fovDegrees = infoFov;
    if (infoFlip) infoRequest.flipUp = true;
    if (infoNoFlip) infoRequest.flipUp = false;
    require(infoBlend == "opaque" || infoBlend == "skip", "--blend-materials " + infoBlend + ": expected opaque or skip");
    infoRequest.skipBlendMaterials = infoBlend == "skip";
    const nlohmann::json facts = sceneInfo(infoRequest);
    if (infoJson)
      std::cout << facts.dump(2) << "\n";
    else
      printSceneInfo(facts, std::cout);
    return 0;
  }

  FrameOptions& fo = *render ? renderOpts : probeOpts;
  fo.checkPath(probe->parsed());
  if (!againstFile.empty()) {
    require(fo.path == "both", "--against " + againstFile + ": probe compares the file's stages with the oracle: add --path both");
    checkForeignStagesFile(againstFile, fo.effect);
    fo.neverSlowerDefault = false;  // as compare: the stages of every level, as `render --never-slower off` writes them
  }
  const Settings settings = fo.settings();
  require(fo.threads >= 0 && fo.threads <= 1024, "--threads: must be in [0, 1024]");
  std::optional<std::pair<int, int>> probePixelXY;
  if (*probe) {
    probePixelXY = parsePixel(pixel);
    require(probePixelXY->first >= 0 && probePixelXY->second >= 0 && probePixelXY->first < settings.width &&
                probePixelXY->second < settings.height,
            "--pixel " + pixel + ": outside the " + fo.size + " image");
  }
  if (*render) {
    require(!out.empty() || !shaded.empty() || !stages.empty() || !report.empty() || !frameOut.empty(),
            "render: nothing to write (give --out, --shaded, --stages or --report)");
    if (!out.empty()) checkOutput(out, "--out", {".exr", ".png"});
    if (!shaded.empty()) checkOutput(shaded, "--shaded", {".exr", ".png"});
    if (!stages.empty()) checkOutput(stages, "--stages", {".exr"});
    if (!frameOut.empty()) checkOutput(frameOut, "--frame-out", {".json"});
    if (!report.empty()) checkOutput(report, "--report", {".json"});
    requireDistinct({{"--out", out}, {"--shaded", shaded}, {"--stages", stages}, {"--report", report}, {"--frame-out", frameOut}});
  }

  // The memory check up front, before the scene is loaded or anything allocated: sizes alone
  // decide it (the scene's diagonal only scales radii).
  const bool keepStages = *probe || !stages.empty();
  int64_t memoryEstimate = estimateFrameBytes(makeConstants(settings, 1.0f), keepStages);
  if (reference) {
    Settings full = settings;
    full.mode = Mode::Full;
    memoryEstimate += estimateFrameBytes(makeConstants(full, 1.0f), false);
  }
  requireMemory(memoryEstimate, memoryLimit(fo.memoryLimitGiB),
                "a " + fo.size + " " + toString(settings.effect) + " frame" + (reference ? " and its reference" : ""));

  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<size_t>(threadCount(fo.threads)));
  const ProgressFn progress = progressPrinter(fo.quiet, toString(settings.mode));
  // The frame's pages are faulted in on a spare core while the scene loads (common/pixel_memory.h).
  PixelReservation pages(static_cast<size_t>(memoryEstimate));
  if (!fo.quiet) std::cerr << "[mrr] loading " << fo.scene << "\n";
  const ResolvedScene rs = resolveScene(fo.sceneRequest());
  if (!fo.quiet) std::cerr << "[mrr] " << rs.scene.triangleCount() << " triangles; building BVH\n";
  const Constants constants = makeConstants(settings, rs.scene.bounds().diagonal());
  // The oracle, or the port: both fill the same FrameResult, so everything after is shared.
  std::unique_ptr<Renderer> cpu;
  std::unique_ptr<gpu::GpuRenderer> port;
  if (fo.path == "both") {  // probe only: the oracle and the port side by side
    const Renderer oracleRenderer(rs.scene);
    std::unique_ptr<gpu::GpuRenderer> portRenderer;  // none with --against: the file's stages instead
    if (againstFile.empty())
      portRenderer = std::make_unique<gpu::GpuRenderer>(rs.scene, fo.glDevice, gpu::parseGpuTiming(fo.gpuTiming));
    const CostModel costs = fo.costModel("cpu");
    const FrameResult o = oracleRenderer.render(rs.camera, constants, {true, progressPrinter(fo.quiet, "oracle"), &costs});
    const FrameResult p = portRenderer ? portRenderer->render(rs.camera, constants, {true, progressPrinter(fo.quiet, "port"), &costs})
                                       : readForeignStages(againstFile, o).frame;
    const nlohmann::json jo = probePixel(o, probePixelXY->first, probePixelXY->second);
    const nlohmann::json jp = probePixel(p, probePixelXY->first, probePixelXY->second);
    const std::string portName = portRenderer ? portRenderer->renderer() : againstFile;
    std::cout << (json ? probeBothJson(jo, jp).dump(2) + "\n" : formatProbeSideBySide(jo, jp, portName));
    return 0;
  }
  if (fo.path == "gpu") {
    port = std::make_unique<gpu::GpuRenderer>(rs.scene, fo.glDevice, gpu::parseGpuTiming(fo.gpuTiming));
    if (!fo.quiet) std::cerr << "[mrr] GL renderer: " << port->renderer() << "\n";
  } else {
    cpu = std::make_unique<Renderer>(rs.scene);
  }
  auto renderWith = [&](const Constants& k, const RenderOptions& o) {
    return port ? port->render(rs.camera, k, o) : cpu->render(rs.camera, k, o);
  };
  // The per-level blend images are debugging output: kept only when something shows them.
  const CostModel costs = fo.costModel(fo.path);
  pages.wait();
  const FrameResult frame = renderWith(constants, {keepStages, progress, &costs});

  if (*probe) {
    const nlohmann::json j = probePixel(frame, probePixelXY->first, probePixelXY->second);
    std::cout << (json ? j.dump(2) + "\n" : formatProbe(j));
    return 0;
  }

  std::optional<FrameErrors> err;
  if (reference) {
    Settings full = settings;
    full.mode = Mode::Full;
    const FrameResult ref = renderWith(makeConstants(full, rs.scene.bounds().diagonal()),
                                       {false, progressPrinter(fo.quiet, "reference")});
    err = errorVsFull(frame, ref);
  }
  RunInfo info{rs.scene.name, rs.scene.credit, fo.path, threadCount(fo.threads), {}, {}};
  if (port) {
    info.renderer = port->renderer();
    info.timingMethod = port->timingMethod();
  }
  info.memoryEstimateBytes = memoryEstimate;
  info.peakResidentBytes = peakResidentBytes();
  if (!out.empty()) writeFinal(out, frame);
  if (!shaded.empty()) writeShaded(shaded, frame);
  const nlohmann::json frameFile = fo.frame(rs, settings);
  if (!stages.empty())
    writeMultiPartExr(stages, stageParts(frame), constants.width, constants.height, {{"mrr:frame", frameFile.dump()}});
  if (!report.empty()) {
    nlohmann::json j = makeReport(frame, info, err);
    j["frame"] = frameFile;
    writeTextFile(report, j.dump(2) + "\n");
  }
  if (!frameOut.empty()) writeTextFile(frameOut, frameFile.dump(2) + "\n");
  if (!fo.quiet) {
    std::cerr << "[mrr] shaded " << frame.shadedPixelsTotal << " of " << constants.width * constants.height
              << " pixels: ideal speedup " << frame.idealSpeedup << "x; total " << frame.timing("total") << " ms\n";
    if (frame.fallback.fellBack)
      std::cerr << "[mrr] never slower: predicted " << frame.fallback.predictedMrrMs << " ms mrr"
                << (frame.fallback.onFloor ? " at the least, before the edge sample,"
                    : frame.fallback.early ? " going on, before the edges,"
                                           : "")
                << " against "
                << frame.fallback.predictedFullMs << " ms full; shaded at full resolution\n";
    if (err)
      std::cerr << "[mrr] vs full: RMS " << err->effect.rms << ", SSIM " << err->effect.ssim << " (shaded: RMS "
                << err->shaded.rms << ")\n";
  }
  return 0;
}

}  // namespace
}  // namespace mrr

int main(int argc, char** argv) {
  // Keep freed image memory in the heap: frames allocate hundreds of MB of same-sized images,
  // and returning them to the kernel makes every next frame page-fault them in again.
  // (M_MMAP_THRESHOLD is capped at 32 MiB, so switch mmap off instead of raising it.)
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, -1);
  mrr::removeTemporariesOnInterrupt();
  try {
    return mrr::run(argc, argv);
  } catch (const mrr::MrrError& e) {
    std::cerr << "mrr: error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "mrr: error: out of memory\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "mrr: error: " << e.what() << "\n";
    return 3;
  }
}
