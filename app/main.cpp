// mrr — the command line: parses, then hands each subcommand to its own file (app/commands.h:
// render and probe in render_command.cpp, compare, check, bench, info; explore/, shaders in byo.cpp).
// Every bad input is one line, "mrr: error: ...", and exit 2.
#include <CLI/CLI.hpp>

#include <malloc.h>
#include <sys/prctl.h>

#include <algorithm>
#include <iostream>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "app/byo.h"
#include "app/commands.h"
#include "app/diff.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/methods.h"
#include <nlohmann/json.hpp>
#include "explore/server.h"
#include "frontend/frame_file.h"

namespace mrr {
namespace {

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

// `mrr explore`: its frame starts small, so that it re-renders in well under a second, and with
// the never-slower rule off, so that it opens on the method's own levels, masks and stencils
// (a small frame often falls back to full; docs/explore.md).
CLI::App* addExploreCommand(CLI::App& app, explore::ServerOptions& o) {
  o.frame.size = "320x180";
  o.frame.samples = 16;
  o.frame.neverSlowerDefault = false;
  CLI::App* explore = app.add_subcommand(
      "explore", "serve a local page on one frame: every stage as a layer, oracle beside port, probes, live knobs");
  o.frame.add(*explore);
  explore->add_option("--port", o.port, "TCP port to serve on (0: any free one; the URL is printed)")->capture_default_str();
  explore->add_option("--host", o.host,
                      "address to listen on (default 127.0.0.1: this machine only; 0.0.0.0 opens it to the network)")
      ->capture_default_str();
  explore->add_option("--budget", o.budget, "most work per request, in millions of sample-pixels (docs/explore.md)")->capture_default_str();
  return explore;
}

int run(int argc, char** argv) {
  CLI::App app{"mrr: multi-resolution rendering of expensive screen-space lighting (Besenthal et al.): "
               "the CPU oracle (cpu_ref/, --path cpu) and the OpenGL 3.3 port (gpu/, --path gpu)"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "help for every subcommand");
  RenderCommand render;
  ProbeCommand probe;
  CompareCommand compare;
  explore::ServerOptions exploreOptions;
  InfoCommand info;
  BenchCommand bench;
  CheckCommand check;
  addRenderCommand(app, render);
  addProbeCommand(app, probe);
  addCompareCommand(app, compare);
  CLI::App* explore = addExploreCommand(app, exploreOptions);
  addInfoCommand(app, info);
  addBenchCommand(app, bench);
  addCheckCommand(app, check);  // `mrr check DIR`, a suite of frames
  // The user's own shaders on every command that runs the port, and `mrr shaders`.
  std::string shaderDir;
  for (CLI::App* c : {render.command, probe.command, compare.command, bench.command, check.command}) addShadersOption(*c, shaderDir);
  ShadersCommand shadersCommand;
  addShadersCommand(app, shadersCommand);
  DiffOptions diff;  // `mrr diff REF TEST` (app/diff.h)
  addDiffCommand(app, diff);
  // `mrr methods`: the method table (common/methods.h), as text or JSON.
  bool methodsJson = false;
  CLI::App* methodsCommand =
      app.add_subcommand("methods", "the methods, one row each: what each shades, its masks, its parameters, its bench variants");
  methodsCommand->add_flag("--json", methodsJson, "print the rows as JSON (as explore's /api/info and the bench's JSON hold them)");

  // --frame F.json stands for the options it holds (frontend/frame_file.h), inserted before the
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

  if (methodsCommand->parsed()) {
    std::cout << (methodsJson ? methodRowsJson().dump(2) + "\n" : methodTableText());
    return 0;
  }
  if (shadersCommand.command->parsed()) return runShadersCommand(shadersCommand);
  if (diff.command->parsed()) return runDiff(diff);
  if (!shaderDir.empty() && *check.command) {
    require(check.against.empty() && check.merge.empty(),
            "check: --shaders " + shaderDir + ": the shaders are the port's; not with --against or --merge");
    check.shaders = shaderDir;
    useShaderDirectory(shaderDir, check.quiet);
  } else if (!shaderDir.empty()) {
    const FrameOptions& f = *render.command ? render.frame : *probe.command ? probe.frame : compare.frame;
    const bool port = *compare.command ||
                      (*bench.command && std::count(bench.paths.begin(), bench.paths.end(), "gpu") > 0) ||
                      ((*render.command || *probe.command) && f.path != "cpu");
    require(port, "--shaders " + shaderDir + ": the shaders are the port's; run it with --path gpu" +
                      (*bench.command ? std::string(" (bench: --paths gpu)") : *probe.command ? " or both" : ""));
    useShaderDirectory(shaderDir, !*bench.command && f.quiet);
  }
  if (*check.command) return runCheckCommand(check);
  if (*bench.command) return runBenchCommand(bench);
  if (*compare.command) return runCompareCommand(compare);
  if (*explore) return explore::serve(exploreOptions);
  if (*info.command) return runInfoCommand(info);
  if (*probe.command) return runProbeCommand(probe);
  return runRenderCommand(render);
}

}  // namespace
}  // namespace mrr

int main(int argc, char** argv) {
  // Keep freed image memory in the heap: frames allocate hundreds of MB of same-sized images,
  // and returning them to the kernel makes every next frame page-fault them in again.
  // (M_MMAP_THRESHOLD is capped at 32 MiB, so switch mmap off instead of raising it.)
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, -1);
  // No transparent huge pages for this process. Measured on the dev VM (kernel THP "madvise",
  // DAMON page-out on): with them, frames after some others in one process ran their G-buffer,
  // edges and shading 3-13x slower than the same work in `full`'s frame (the kernel zeroing huge
  // pages at 13% of the samples), at random by the methods' mix; without, every method's frame
  // times are steady (docs/figures.md). Best effort: an old kernel refuses it.
  prctl(PR_SET_THP_DISABLE, 1, 0, 0, 0);
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
