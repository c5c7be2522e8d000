// `mrr compare`: the oracle and the port on the same frame, every stage compared (SPEC §8).
// Exit 0 when every stage is within tolerance, 1 when one is not, 2 on bad input. With
// `--against FILE`: the oracle against another renderer's stages (compare/parity/against.h);
// the port does not run.
#include <tbb/global_control.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>

#include "app/byo.h"
#include "app/commands.h"
#include "common/error.h"
#include "common/memory.h"
#include "compare/parity/against.h"
#include "compare/parity/constant_effect.h"
#include "compare/parity/html_report.h"
#include "compare/parity/noise.h"
#include "compare/parity/parity.h"
#include "compare/report/report_python.h"
#include "frontend/renderers.h"

namespace mrr {

void addCompareCommand(CLI::App& app, CompareCommand& c) {
  c.command = app.add_subcommand("compare", "run the oracle and the GL port on one frame and compare every stage");
  c.frame.add(*c.command);
  c.command->add_option("--report", c.reportDir, "also write a self-contained HTML report into this folder");
  addAgainstOption(*c.command, c.against);
  c.command->add_flag("--noise-aware", c.noiseAware,
                      "ssao/ssgi: judge the stochastic stages (raw.L*, sub.L*, final, shaded) statistically against "
                      "the oracle rendered with " + std::to_string(kNoiseRule.seeds) +
                          " independent seeds, for a renderer with its own noise (another --seed, blue noise); "
                          "the deterministic stages keep their exact rules (docs/compare.md)");
}

namespace {

// The settings of each effect compared: --effect all is the three, each at its own default
// sample count unless --samples gives one.
std::vector<Settings> comparedSettings(const FrameOptions& fo) {
  std::vector<std::string> effects = {fo.effect};
  if (fo.effect == "all") effects = {"ssao", "ssm", "ssgi"};
  std::vector<Settings> settings;
  for (const std::string& e : effects) {
    FrameOptions one = fo;
    one.effect = e;
    settings.push_back(one.settings());
  }
  return settings;
}

// The report's page: every effect's two frames, and the command that reproduces them exactly
// (the camera and light as resolved).
void writeReport(const CompareCommand& c, const ResolvedScene& rs, const std::vector<Settings>& settings,
                 const std::string& subjectName, const std::vector<ComparedFrame>& compared) {
  const FrameOptions& fo = c.frame;
  nlohmann::json frame = fo.frame(rs, settings.front());
  if (settings.size() > 1) {  // one command for every effect, each at its own sample count unless given
    frame["effect"] = "all";
    if (!fo.samples) frame.erase("samples");
  }
  std::string command = "mrr compare " + frameCommandLine(frame);
  const std::string label = fo.scene == rs.scene.name
                                ? rs.scene.name
                                : fo.scene + " (" + std::filesystem::path(rs.scene.name).filename().string() + ")";
  if (!c.against.empty()) command += " --against " + c.against;
  CompareReportInfo info{label, rs.scene.credit, subjectName, command};
  if (!c.against.empty()) info.subject = c.against + " (another renderer's stages)";
  writeCompareReport(c.reportDir, info, compared);
  if (!fo.quiet) std::cerr << "[mrr] wrote " << (std::filesystem::path(c.reportDir) / "index.html").string() << "\n";
}

}  // namespace

std::vector<Settings> prepareCompare(CompareCommand& c) {
  FrameOptions& fo = c.frame;
  fo.checkPath();
  if (!c.against.empty()) checkForeignStagesFile(c.against, fo.effect);
  fo.neverSlowerDefault = false;
  const std::vector<Settings> settings = comparedSettings(fo);
  require(fo.threads >= 0 && fo.threads <= 1024, optionName(Param::Threads) + ": must be in " + paramRange(Param::Threads));
  if (!c.reportDir.empty()) {
    requireReportPython();  // before the folder is made: a missing package writes nothing
    makeReportDir(c.reportDir);
  }
  int64_t memory = 0;
  for (const Settings& s : settings) memory = std::max(memory, 2 * estimateFrameBytes(makeConstants(s, 1.0f), true));
  requireMemory(memory, memoryLimit(fo.memoryLimitGiB), "comparing a " + fo.size + " frame on both paths");
  return settings;
}

namespace {

// "raw.L0: ssao.same_input max|d| 0.03  rms 0.0269  over 85.4% of 12036": the check that decided
// the row's FAIL (its same-input check when that fails, else its end-to-end one).
std::string failingFigures(const ParityResult& result) {
  for (const StageRow& r : result.rows) {
    if (r.verdict() != "FAIL") continue;
    const std::optional<StageCheck>& check = r.sameInput && !r.sameInput->pass ? r.sameInput : r.endToEnd;
    std::ostringstream text;
    if (check && check->noise) text << "noise-aware: " << check->noise->describe();
    else if (check) text << check->rule << " " << check->figures;
    return text.str();
  }
  return {};
}

}  // namespace

CompareOutcome compareFrame(const CompareCommand& c, const std::vector<Settings>& settings, std::ostream* out,
                            std::mutex* portLock) {
  const FrameOptions& fo = c.frame;
  if (!fo.quiet) std::cerr << "[mrr] loading " << fo.scene << "\n";
  const ResolvedScene rs = resolveScene(fo.sceneRequest());
  const std::unique_ptr<FrameRenderer> oracle = makeRenderer("cpu", rs.scene);
  const bool usePort = c.against.empty();  // else the file's stages
  std::unique_ptr<FrameRenderer> port;     // with a portLock: made, used and closed under it, per frame
  if (usePort && !portLock) port = makeRenderer("gpu", rs.scene, fo.pathOptions());
  std::string subjectName = port ? port->device() : c.against;
  if (!fo.quiet && port) std::cerr << "[mrr] GL renderer: " << port->device() << "\n";
  CompareOutcome outcome;
  // Frames are kept for the HTML report (two frames with every stage per effect).
  std::vector<std::unique_ptr<FrameResult>> kept;
  std::vector<ComparedFrame> compared;
  const CostModel costs = fo.costModel("cpu");
  for (const Settings& s : settings) {
    const Constants k = makeConstants(s, rs.framed.size);
    // SPEC §14: each path's own previous frame first, where the temporal term reads one
    const FrameHistory oracleBefore = previousFrameHistory(*oracle, rs.camera, s, rs.framed.size, &costs);
    RenderOptions oracleOptions{true, progressPrinter(fo.quiet, "oracle"), &costs};
    if (!oracleBefore.empty()) oracleOptions.history = &oracleBefore;
    auto reference = std::make_unique<FrameResult>(oracle->render(rs.camera, k, oracleOptions));
    if (effectIsConstant(*reference)) {  // two black frames agree, and check nothing
      const EffectRange range = effectRange(*reference);
      std::cerr << "mrr: warning: " << toString(s.effect) << ": the oracle's effect is " << range.lo
                << " at every surface pixel of the view, so this comparison checks little; light the view with "
                << optionName(Param::LightDir) << " x,y,z (`mrr info " << fo.scene << "` prints the light used)\n";
    }
    std::unique_ptr<FrameResult> subject;
    ParityResult result;
    std::string notChecked;
    if (usePort) {
      RenderOptions options{true, progressPrinter(fo.quiet, "port"), &costs};
      const auto renderPort = [&](const FrameRenderer& r) {
        const FrameHistory before = previousFrameHistory(r, rs.camera, s, rs.framed.size, &costs);
        if (!before.empty()) options.history = &before;
        return std::make_unique<FrameResult>(r.render(rs.camera, k, options));
      };
      if (portLock) {
        const std::lock_guard<std::mutex> lock(*portLock);
        const std::unique_ptr<FrameRenderer> one = makeRenderer("gpu", rs.scene, fo.pathOptions());
        subjectName = one->device();
        subject = renderPort(*one);
      } else {
        subject = renderPort(*port);
      }
      result = compareFrames(*reference, *subject, rs.scene.light);
    } else {
      ForeignStages foreign = readForeignStages(c.against, *reference);
      for (const std::string& n : foreign.ignored)
        std::cerr << "mrr: warning: --against " << c.against << ": part " << n << " names no stage; not checked\n";
      result = compareForeign(*reference, foreign, rs.scene.light);
      notChecked = formatNotChecked(foreign);
      subject = std::make_unique<FrameResult>(std::move(foreign.frame));
    }
    if (c.noiseAware && isStochastic(s.effect)) {
      // The oracle's stochastic stages over K independent seeds (compare/parity/noise.h).
      const NoiseReference noise = buildNoiseReference(
          [&](uint32_t seed) {
            Settings seeded = s;
            seeded.seed = seed;
            return oracle->render(rs.camera, makeConstants(seeded, rs.framed.size), {true, {}, &costs});
          },
          k.samples(), [&](int i, int n) {
            if (!fo.quiet) std::cerr << "[mrr] noise-aware: oracle seed " << i + 1 << "/" << n << "\n";
          });
      applyNoiseAware(result, *reference, *subject, noise);
    } else if (c.noiseAware && !fo.quiet) {
      std::cerr << "[mrr] noise-aware: " << toString(s.effect) << " has no stochastic stage; every stage exact\n";
    }
    std::ostringstream table;
    if (&s != &settings.front()) table << "\n";  // the last line is the verdict
    const bool effectOnly = methodInfo(s.mode).owns(Param::EffectOnly) && s.effectMask.effectOnly;  // SPEC §12.3: say which arm
    table << "== compare " << rs.scene.name << ", " << toString(s.effect) << ", " << toString(s.mode)
          << (effectOnly ? " (effect only)" : "") << ", "
          << s.width << "x" << s.height << ", " << k.samples() << " samples; oracle (cpu_ref) vs "
          << (usePort ? "port (" + subjectName + ")" : c.against) << "\n"
          << notChecked << formatParityTable(result, usePort ? "the port's" : "the file's");
    if (out) *out << table.str();
    outcome.tables += table.str();
    if (!result.pass() && outcome.pass) {
      outcome.pass = false;
      outcome.effect = toString(s.effect);
      outcome.firstFailing = (settings.size() > 1 ? outcome.effect + ":" : "") + result.firstFailing();
      outcome.figures = failingFigures(result);
    }
    if (!c.reportDir.empty()) {
      std::string probe = "mrr probe --path both " + (c.against.empty() ? "" : "--against " + c.against + " ") +
                          frameCommandLine(fo.frame(rs, s));
      compared.push_back({toString(s.effect), reference.get(), subject.get(), std::move(result), probe});
      kept.push_back(std::move(reference));
      kept.push_back(std::move(subject));
    }
  }
  outcome.subject = subjectName;
  outcome.scene = rs.scene.name;
  if (!c.reportDir.empty()) writeReport(c, rs, settings, subjectName, compared);
  return outcome;
}

int runCompareCommand(CompareCommand& c) {
  const std::vector<Settings> settings = prepareCompare(c);
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threadCount(c.frame.threads)));
  return compareFrame(c, settings, &std::cout).pass ? 0 : 1;
}

}  // namespace mrr
