// `mrr check DIR`: a validation suite. Every frame file DIR/CASE.json is one case, one
// `compare` of its frame (app/compare_command.cpp: compareFrame): the oracle against the port,
// the port with --shaders SDIR, or --against ADIR's stages (ADIR/CASE.exr or ADIR/CASE/). One
// verdict: exit 0 when every case passes, 1 when one fails, 2 when one could not run (or on a
// usage error). --noise-aware judges each SSAO/SSGI case's stochastic stages as `compare
// --noise-aware` does. --shard I/N runs the cases whose name hashes to shard I; --json writes the
// results, and `check --merge R1.json R2.json …` joins shards' results into one summary, JUnit
// file and report (compare/suite/suite.h holds everything that does not render).
//
// --jobs K runs K cases side by side, each with its share of the threads (a tbb::task_arena per
// job). The port renders one frame at a time: each frame's port render makes, uses and closes its
// own GL context under one lock, since EGL's display is one per process and a context is current
// on one thread. The oracle halves, which take most of the time, overlap.
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <new>
#include <thread>

#include "app/commands.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/tolerance.h"
#include "compare/report/report_python.h"
#include "compare/suite/suite.h"
#include "frontend/frame_file.h"

namespace mrr {

namespace fs = std::filesystem;

void addCheckCommand(CLI::App& app, CheckCommand& c) {
  c.command = app.add_subcommand(
      "check", "a validation suite: compare every frame file (*.json) in DIR, one verdict, JUnit, shards (docs/validate-your-own.md)");
  c.command->add_option("DIR", c.dir, "the suite: a folder of frame files (`mrr render --frame-out`), one case each, named after its file");
  c.command->add_option("--against", c.against,
                        "another renderer's stages instead of the port: a folder holding CASE.exr or CASE/ for each case");
  c.command->add_option("--junit", c.junit, "also write JUnit XML (one testcase per case) to this .xml file");
  c.command->add_option("--json", c.json, "also write the results as JSON, for `mrr check --merge`");
  c.command->add_option("--report", c.reportDir,
                        "also write HTML: each case's compare page in FOLDER/CASE/ and an index, FOLDER/index.html");
  c.command->add_option("--shard", c.shard,
                        "run shard I of N (I/N, e.g. 2/4): the cases whose name hashes to it (FNV-1a); the N shards partition the suite");
  c.command->add_option("--jobs", c.jobs, "cases run side by side, the threads divided between them (the port runs one frame at a time)")
      ->capture_default_str();
  c.command->add_option(optionName(Param::Threads), c.threads, "worker threads in all (0 = all cores)")->capture_default_str();
  c.command->add_option(optionName(Param::GlDevice), c.glDevice, paramHelp(Param::GlDevice));
  c.command->add_option("--merge", c.merge, "join the --json results of shards (R1.json R2.json ...) instead of running DIR")
      ->expected(1, -1);
  c.command->add_flag("--noise-aware", c.noiseAware,
                      "ssao/ssgi cases: judge the stochastic stages against the oracle's independent seeds, as "
                      "compare --noise-aware does (for a renderer with its own noise)");
  c.command->add_flag("-q,--quiet", c.quiet, "no progress lines on stderr");
}

namespace {

using Clock = std::chrono::steady_clock;

// The case's frame as compare's options: the frame file's words parsed by the options compare
// registers, then check's own (quiet, the job's threads, the GL device).
FrameOptions caseFrame(const nlohmann::json& frame, const std::string& file) {
  const std::vector<std::string> words = frameArgs(frame, file);
  FrameOptions fo;
  CLI::App parser;
  fo.add(parser);
  try {
    parser.parse(std::vector<std::string>(words.rbegin(), words.rend()));  // CLI11 takes them last to first
  } catch (const CLI::ParseError& e) {
    throw MrrError(file + ": " + e.what());
  }
  return fo;
}

// ADIR/CASE.exr, else ADIR/CASE/.
std::string caseStages(const std::string& againstDir, const std::string& name) {
  std::error_code ec;
  const fs::path file = fs::path(againstDir) / (name + ".exr"), folder = fs::path(againstDir) / name;
  if (fs::is_regular_file(file, ec)) return file.string();
  if (fs::is_directory(folder, ec)) return folder.string();
  throw MrrError("--against " + againstDir + ": no stages for case " + name + " (expected " + file.string() + " or " +
                 folder.string() + "/)");
}

struct CaseRun {
  const CheckCommand& c;
  int threadsPerJob = 1;
  std::mutex* portLock = nullptr;
};

CaseResult runCase(const CaseRun& run, const std::string& name, std::string& subject) {
  const CheckCommand& c = run.c;
  CaseResult r;
  r.name = name;
  const Clock::time_point start = Clock::now();
  try {
    const std::string file = (fs::path(c.dir) / (name + ".json")).string();
    const nlohmann::json frame = readJsonObjectFile(file, "frame file");
    // What the file names, for the summary even when it is broken.
    const auto text = [&](const char* key) { return frame.contains(key) && frame[key].is_string() ? frame[key].get<std::string>() : ""; };
    CompareCommand compare;
    compare.frame = FrameOptions{};
    r.effect = text("effect").empty() ? compare.frame.effect : text("effect");
    r.method = text("method").empty() ? compare.frame.mode : text("method");
    r.scene = text("scene").empty() ? compare.frame.scene : text("scene");
    r.size = text("size").empty() ? compare.frame.size : text("size");
    compare.frame = caseFrame(frame, file);
    compare.frame.quiet = true;
    compare.frame.threads = run.threadsPerJob;
    compare.frame.glDevice = c.glDevice;
    if (!c.against.empty()) compare.against = caseStages(c.against, name);
    compare.noiseAware = c.noiseAware;
    const std::vector<Settings> settings = prepareCompare(compare);
    if (!c.reportDir.empty()) {
      compare.reportDir = (fs::path(c.reportDir) / name).string();
      makeReportDir(compare.reportDir, "--report");
    }
    const CompareOutcome outcome = compareFrame(compare, settings, nullptr, run.portLock);
    subject = outcome.subject;
    r.scene = outcome.scene;
    r.verdict = outcome.pass ? "PASS" : "FAIL";
    if (!outcome.pass) {
      r.stage = outcome.firstFailing;
      r.message = "first failing stage " + outcome.firstFailing + ": " + outcome.figures;
      r.details = outcome.tables;
    }
    if (!c.reportDir.empty()) r.page = name + "/index.html";
  } catch (const MrrError& e) {
    r.verdict = "ERROR";
    r.message = e.what();
  } catch (const std::bad_alloc&) {
    r.verdict = "ERROR";
    r.message = "out of memory";
  } catch (const std::exception& e) {
    r.verdict = "ERROR";
    r.message = e.what();
  }
  if (r.verdict == "ERROR" && !c.reportDir.empty()) {  // no page: no empty folder beside the others
    std::error_code ec;
    const fs::path folder = fs::path(c.reportDir) / name;
    if (fs::is_directory(folder, ec) && fs::is_empty(folder, ec)) fs::remove(folder, ec);
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

// The output options, checked before any case runs.
void checkOutputs(const CheckCommand& c) {
  if (!c.junit.empty()) checkOutput(c.junit, "--junit", {".xml"});
  if (!c.json.empty()) checkOutput(c.json, "--json", {".json"});
  requireDistinct({{"--junit", c.junit}, {"--json", c.json}});
  if (!c.reportDir.empty()) {
    requireReportPython();
    makeReportDir(c.reportDir);
  }
}

int finish(const CheckCommand& c, const SuiteResults& results) {
  std::cout << formatSummary(results);
  if (!c.junit.empty()) writeTextFile(c.junit, junitXml(results));
  if (!c.json.empty()) writeTextFile(c.json, resultsJson(results).dump(2) + "\n");
  if (!c.reportDir.empty()) {
    writeSuiteIndex(c.reportDir, results);
    if (!c.quiet) std::cerr << "[mrr] wrote " << (fs::path(c.reportDir) / "index.html").string() << "\n";
  }
  return suiteExitCode(results);
}

int runMerge(const CheckCommand& c) {
  require(c.dir.empty(), "check: a folder or --merge, not both (--merge joins results already run)");
  require(c.against.empty() && c.shard.empty() && c.shaders.empty() && !c.noiseAware,
          "check --merge: --against, --shard, --shaders and --noise-aware are for running a suite, not for merging "
          "results");
  std::vector<SuiteResults> parts;
  for (const std::string& f : c.merge) parts.push_back(resultsFromJson(readJsonObjectFile(f, "--merge"), "--merge " + f));
  const SuiteResults merged = mergeResults(parts, c.merge);
  checkOutputs(c);
  return finish(c, merged);
}

}  // namespace

int runCheckCommand(CheckCommand& c) {
  if (!c.merge.empty()) return runMerge(c);
  require(!c.dir.empty(), "check: a folder of frame files is required (mrr check DIR), or --merge R1.json R2.json ...");
  require(c.jobs >= 1 && c.jobs <= 256, "--jobs " + std::to_string(c.jobs) + ": must be in [1, 256]");
  require(c.threads >= 0 && c.threads <= 1024, "--threads " + std::to_string(c.threads) + ": must be in [0, 1024]");
  const Shard shard = c.shard.empty() ? Shard{} : parseShard(c.shard);
  const std::vector<std::string> all = suiteCases(c.dir);
  if (!c.against.empty()) {
    std::error_code ec;
    require(fs::is_directory(c.against, ec),
            "--against " + c.against + ": no such folder (check takes a folder with CASE.exr or CASE/ per case)");
  }
  if (!c.json.empty()) {  // a results file among the frame files would be read as a case next time
    std::error_code ec;
    const fs::path parent = fs::absolute(c.json).parent_path();
    require(!fs::equivalent(parent, c.dir, ec), "--json " + c.json + ": inside the suite's folder " + c.dir +
                                                    ", it would be read as a case; write it elsewhere");
  }
  checkOutputs(c);

  SuiteResults results;
  results.suite = c.dir;
  results.shard = shard;
  results.casesInSuite = static_cast<int>(all.size());
  std::vector<std::string> names;
  for (const std::string& n : all)
    if (inShard(n, shard)) names.push_back(n);

  const int threads = threadCount(c.threads);
  const int jobs = std::max(1, std::min<int>(c.jobs, static_cast<int>(names.size())));
  std::mutex portLock, printLock;
  const CaseRun shared{c, std::max(1, threads / jobs), jobs > 1 ? &portLock : nullptr};
  const std::string what = (!c.against.empty() ? "--against " + c.against
                            : !c.shaders.empty() ? "the port with --shaders " + c.shaders
                                                 : std::string("the port")) +
                           (c.noiseAware ? ", noise-aware" : "");
  if (!c.quiet)
    std::cerr << "[mrr] check " << c.dir << ": " << names.size() << " of " << all.size() << " cases"
              << (shard.count > 1 ? " (shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) + ")" : "")
              << ", oracle against " << what << "; " << jobs << (jobs == 1 ? " job, " : " jobs, ") << shared.threadsPerJob
              << (shared.threadsPerJob == 1 ? " thread" : " threads") << (jobs == 1 ? "" : " each") << "\n";

  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  results.cases.resize(names.size());
  std::atomic<size_t> next{0};
  size_t done = 0;
  std::string subject;
  const auto worker = [&] {
    tbb::task_arena arena(shared.threadsPerJob);
    for (size_t i = next++; i < names.size(); i = next++) {
      std::string device;
      CaseResult r;
      arena.execute([&] { r = runCase(shared, names[i], device); });
      const std::lock_guard<std::mutex> lock(printLock);
      if (subject.empty()) subject = device;
      ++done;
      if (!c.quiet) {
        char time[32];
        std::snprintf(time, sizeof time, "%.2f s", r.seconds);
        std::cerr << "[mrr] check " << done << "/" << names.size() << " " << r.name << ": " << r.verdict
                  << (r.verdict == "FAIL" ? " at " + r.stage : r.verdict == "ERROR" ? ": " + r.message : "") << " (" << time
                  << ")\n";
      }
      results.cases[i] = std::move(r);
    }
  };
  std::vector<std::thread> workers;
  for (int j = 1; j < jobs; ++j) workers.emplace_back(worker);
  worker();
  for (std::thread& t : workers) t.join();

  results.subject = (!c.against.empty() ? "--against " + c.against
                     : "the GL port" + (c.shaders.empty() ? std::string() : " with --shaders " + c.shaders) +
                           (subject.empty() ? "" : " (" + subject + ")")) +
                    (c.noiseAware ? ", noise-aware (the stochastic stages against the oracle's " +
                                        std::to_string(kNoiseRule.seeds) + " seeds)"
                                  : "");
  return finish(c, results);
}

}  // namespace mrr
