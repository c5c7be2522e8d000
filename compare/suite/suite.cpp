#include "compare/suite/suite.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "common/error.h"
#include "common/image_io.h"
#include "compare/report/report_python.h"

namespace mrr {

namespace fs = std::filesystem;

namespace {

std::string seconds(double s, const char* format = "%.2f") {
  char text[32];
  std::snprintf(text, sizeof text, format, s);
  return text;
}

std::string plural(size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// XML text and attribute values: the five entities escaped, control characters XML 1.0 cannot
// hold dropped (tabs and newlines kept).
std::string xmlEscape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t' && c != '\r') break;
        out += c;
    }
  }
  return out;
}

size_t countVerdict(const SuiteResults& r, const std::string& verdict) {
  return static_cast<size_t>(
      std::count_if(r.cases.begin(), r.cases.end(), [&](const CaseResult& c) { return c.verdict == verdict; }));
}

std::string shardText(const Shard& s) { return std::to_string(s.index) + "/" + std::to_string(s.count); }

}  // namespace

std::vector<std::string> suiteCases(const std::string& dir) {
  std::error_code ec;
  require(fs::is_directory(dir, ec), "check " + dir + ": no such folder (expected a folder of frame files, *.json)");
  std::vector<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const fs::path& p = e.path();
    if (p.extension() == ".json" && e.is_regular_file(ec)) names.push_back(p.stem().string());
  }
  require(!ec, "check " + dir + ": cannot list the folder: " + ec.message());
  require(!names.empty(), "check " + dir + ": holds no frame file (*.json, as `mrr render --frame-out` writes)");
  std::sort(names.begin(), names.end());
  return names;
}

Shard parseShard(const std::string& text) {
  Shard s;
  char slash = 0, rest = 0;
  require(std::sscanf(text.c_str(), "%d%c%d%c", &s.index, &slash, &s.count, &rest) == 3 && slash == '/' &&
              s.count >= 1 && s.index >= 1 && s.index <= s.count,
          "--shard " + text + ": expected I/N with 1 <= I <= N, e.g. 1/4");
  return s;
}

uint64_t caseHash(const std::string& name) {
  uint64_t h = 14695981039346656037ull;  // FNV-1a, 64 bits
  for (const char c : name) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

bool inShard(const std::string& name, const Shard& shard) {
  return caseHash(name) % static_cast<uint64_t>(shard.count) == static_cast<uint64_t>(shard.index - 1);
}

std::string formatSummary(const SuiteResults& r) {
  const std::vector<std::string> head = {"case", "effect", "method", "verdict", "first failing stage", "time"};
  std::vector<std::vector<std::string>> rows;
  for (const CaseResult& c : r.cases)
    rows.push_back({c.name, c.effect, c.method, c.verdict, c.stage.empty() ? "-" : c.stage, seconds(c.seconds) + " s"});
  std::vector<size_t> width(head.size());
  for (size_t i = 0; i < head.size(); ++i) {
    width[i] = head[i].size();
    for (const auto& row : rows) width[i] = std::max(width[i], row[i].size());
  }
  const auto line = [&](const std::vector<std::string>& cells) {
    std::string out;
    for (size_t i = 0; i < cells.size(); ++i) {
      const bool last = i + 1 == cells.size();
      // The time is right-aligned; the rest left-aligned, two spaces apart.
      if (last) out += std::string(width[i] - cells[i].size(), ' ') + cells[i];
      else out += cells[i] + std::string(width[i] - cells[i].size() + 2, ' ');
    }
    return out + "\n";
  };
  std::string out = line(head);
  for (const auto& row : rows) out += line(row);
  for (const CaseResult& c : r.cases)
    if (c.verdict != "PASS") out += c.name + ": " + c.verdict + ": " + c.message + "\n";

  const size_t n = r.cases.size(), failed = countVerdict(r, "FAIL"), errors = countVerdict(r, "ERROR");
  std::string of = plural(n, "case", "cases");
  if (r.shard.count > 1) of += " of shard " + shardText(r.shard) + " (the suite has " + std::to_string(r.casesInSuite) + ")";
  if (errors > 0)
    out += "ERROR: " + std::to_string(errors) + " of " + of + " could not run; " + std::to_string(failed) + " failed\n";
  else if (failed > 0)
    out += "FAIL: " + std::to_string(failed) + " of " + of + " failed\n";
  else if (n == 0)
    out += "PASS: shard " + shardText(r.shard) + " holds none of the suite's " + std::to_string(r.casesInSuite) + " cases\n";
  else
    out += "PASS: " + std::string(n == 1 ? "" : "all ") + of + "\n";
  return out;
}

int suiteExitCode(const SuiteResults& r) {
  if (countVerdict(r, "ERROR") > 0) return 2;
  return countVerdict(r, "FAIL") > 0 ? 1 : 0;
}

std::string junitXml(const SuiteResults& r) {
  double total = 0.0;
  for (const CaseResult& c : r.cases) total += c.seconds;
  const std::string counts = "tests=\"" + std::to_string(r.cases.size()) + "\" failures=\"" +
                             std::to_string(countVerdict(r, "FAIL")) + "\" errors=\"" +
                             std::to_string(countVerdict(r, "ERROR")) + "\" time=\"" + seconds(total, "%.3f") + "\"";
  std::string name = "mrr check " + r.suite;
  if (r.shard.count > 1) name += " (shard " + shardText(r.shard) + ")";
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<testsuites name=\"" + xmlEscape(name) + "\" " + counts + ">\n";
  out += "  <testsuite name=\"" + xmlEscape(name) + "\" " + counts + " skipped=\"0\">\n";
  out += "    <properties>\n      <property name=\"subject\" value=\"" + xmlEscape(r.subject) + "\"/>\n    </properties>\n";
  for (const CaseResult& c : r.cases) {
    const std::string classname = c.effect == "-" ? "mrr.check" : "mrr.check." + c.effect;
    out += "    <testcase classname=\"" + xmlEscape(classname) + "\" name=\"" + xmlEscape(c.name) + "\" time=\"" +
           seconds(c.seconds, "%.3f") + "\"";
    if (c.verdict == "PASS") {
      out += "/>\n";
      continue;
    }
    const std::string tag = c.verdict == "FAIL" ? "failure" : "error";
    out += ">\n      <" + tag + " message=\"" + xmlEscape(c.message) + "\" type=\"" + c.verdict + "\">" +
           xmlEscape(c.details.empty() ? c.message : c.details) + "</" + tag + ">\n    </testcase>\n";
  }
  out += "  </testsuite>\n</testsuites>\n";
  return out;
}

nlohmann::json resultsJson(const SuiteResults& r) {
  nlohmann::json cases = nlohmann::json::array();
  for (const CaseResult& c : r.cases)
    cases.push_back({{"name", c.name}, {"effect", c.effect}, {"method", c.method}, {"scene", c.scene},
                     {"size", c.size}, {"verdict", c.verdict}, {"stage", c.stage}, {"message", c.message},
                     {"details", c.details}, {"seconds", c.seconds}, {"page", c.page}});
  return {{"mrr_check", 1},
          {"suite", r.suite},
          {"subject", r.subject},
          {"shard", {{"index", r.shard.index}, {"count", r.shard.count}}},
          {"cases_in_suite", r.casesInSuite},
          {"cases", std::move(cases)}};
}

SuiteResults resultsFromJson(const nlohmann::json& j, const std::string& source) {
  require(j.is_object() && j.value("mrr_check", 0) == 1,
          source + ": not the results of `mrr check --json` (no \"mrr_check\": 1)");
  SuiteResults r;
  try {
    r.suite = j.at("suite").get<std::string>();
    r.subject = j.at("subject").get<std::string>();
    r.shard.index = j.at("shard").at("index").get<int>();
    r.shard.count = j.at("shard").at("count").get<int>();
    r.casesInSuite = j.at("cases_in_suite").get<int>();
    for (const nlohmann::json& c : j.at("cases")) {
      CaseResult x;
      x.name = c.at("name").get<std::string>();
      x.effect = c.at("effect").get<std::string>();
      x.method = c.at("method").get<std::string>();
      x.scene = c.value("scene", "");
      x.size = c.value("size", "");
      x.verdict = c.at("verdict").get<std::string>();
      x.stage = c.value("stage", "");
      x.message = c.value("message", "");
      x.details = c.value("details", "");
      x.seconds = c.value("seconds", 0.0);
      x.page = c.value("page", "");
      require(x.verdict == "PASS" || x.verdict == "FAIL" || x.verdict == "ERROR",
              source + ": case " + x.name + ": verdict " + x.verdict + " (expected PASS, FAIL or ERROR)");
      r.cases.push_back(std::move(x));
    }
  } catch (const nlohmann::json::exception& e) {
    throw MrrError(source + ": not the results of `mrr check --json`: " + e.what());
  }
  require(r.shard.count >= 1 && r.shard.index >= 1 && r.shard.index <= r.shard.count,
          source + ": shard " + shardText(r.shard) + " is no shard");
  return r;
}

SuiteResults mergeResults(const std::vector<SuiteResults>& parts, const std::vector<std::string>& sources) {
  require(!parts.empty(), "--merge: no results to merge");
  SuiteResults out;
  out.suite = parts.front().suite;
  out.casesInSuite = parts.front().casesInSuite;
  const int count = parts.front().shard.count;
  std::map<int, std::string> seen;  // shard index -> the file that holds it
  std::map<std::string, std::string> owner;  // case -> the file that holds it
  std::set<std::string> subjects;
  for (size_t i = 0; i < parts.size(); ++i) {
    const SuiteResults& p = parts[i];
    const std::string& source = sources.at(i);
    require(p.shard.count == count, "--merge: " + source + " is shard " + shardText(p.shard) + ", " + sources.front() +
                                        " one of " + std::to_string(count) + ": not one suite's shards");
    require(p.casesInSuite == out.casesInSuite,
            "--merge: " + source + " comes from a suite of " + std::to_string(p.casesInSuite) + " cases, " +
                sources.front() + " from one of " + std::to_string(out.casesInSuite) + ": not one suite's shards");
    const auto [at, fresh] = seen.emplace(p.shard.index, source);
    require(fresh, "--merge: " + source + " and " + at->second + " are both shard " + shardText(p.shard));
    if (subjects.insert(p.subject).second) out.subject += (out.subject.empty() ? "" : "; ") + p.subject;
    for (const CaseResult& c : p.cases) {
      const auto [where, added] = owner.emplace(c.name, source);
      require(added, "--merge: case " + c.name + " is in " + where->second + " and in " + source);
      out.cases.push_back(c);
    }
  }
  std::string missing;
  for (int s = 1; s <= count; ++s)
    if (!seen.count(s)) missing += (missing.empty() ? "" : ", ") + std::to_string(s) + "/" + std::to_string(count);
  require(missing.empty(), "--merge: shard " + missing + " missing (give every shard's --json results)");
  require(static_cast<int>(out.cases.size()) == out.casesInSuite,
          "--merge: the shards hold " + std::to_string(out.cases.size()) + " cases, their suite " +
              std::to_string(out.casesInSuite) + " (did its folder change between the shards' runs?)");
  std::sort(out.cases.begin(), out.cases.end(), [](const CaseResult& a, const CaseResult& b) { return a.name < b.name; });
  return out;
}

void writeSuiteIndex(const std::string& dir, const SuiteResults& r) {
  nlohmann::json cases = nlohmann::json::array();
  double total = 0.0;
  for (const CaseResult& c : r.cases) {
    std::error_code ec;
    const bool linked = !c.page.empty() && fs::exists(fs::path(dir) / c.page, ec);
    total += c.seconds;
    // The failing stage's section of the page: compare.html.j2's anchors are EFFECT-STAGE.
    std::string stageLink;
    if (linked && c.verdict == "FAIL") {
      const size_t colon = c.stage.find(':');
      stageLink = c.page + "#" + (colon == std::string::npos ? c.effect + "-" + c.stage
                                                              : c.stage.substr(0, colon) + "-" + c.stage.substr(colon + 1));
    }
    cases.push_back({{"name", c.name}, {"stage_link", stageLink}, {"effect", c.effect}, {"method", c.method}, {"scene", c.scene},
                     {"size", c.size}, {"verdict", c.verdict}, {"stage", c.stage}, {"message", c.message},
                     {"time", seconds(c.seconds) + " s"}, {"page", linked ? c.page : ""}});
  }
  std::string summary = formatSummary(r);
  summary.pop_back();
  const nlohmann::json data = {{"kind", "check"},
                               {"suite", r.suite},
                               {"subject", r.subject},
                               {"shard", r.shard.count > 1 ? shardText(r.shard) : ""},
                               {"cases_in_suite", r.casesInSuite},
                               {"passed", countVerdict(r, "PASS")},
                               {"failed", countVerdict(r, "FAIL")},
                               {"errors", countVerdict(r, "ERROR")},
                               {"time", seconds(total) + " s"},
                               {"verdict", summary.substr(summary.rfind('\n') + 1)},
                               {"cases", std::move(cases)}};
  ReportJob job;
  writeTextFile((fs::path(dir) / "index.html").string(), job.makePage(data));
}

}  // namespace mrr
