#pragma once
// Validation suites (`mrr check DIR`): a folder of frame files, one compare each, one
// verdict. This file holds what does not render: the cases of a folder, the shard a case falls
// in, the summary table, JUnit XML, the results as JSON (what `check --json` writes and
// `check --merge` reads back) and the report's index page. app/check_command.cpp runs the cases.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mrr {

// One case's outcome. verdict: "PASS", "FAIL" (a stage over its tolerance) or "ERROR" (the
// case could not run: a broken frame file, missing stages, a shader that does not compile).
struct CaseResult {
  std::string name;            // the frame file's name without ".json"
  std::string effect = "-";    // as the frame file names them ("-" when it cannot be read)
  std::string method = "-";
  std::string scene, size;     // for the report's index ("" when unknown)
  std::string verdict;         // PASS, FAIL or ERROR
  std::string stage;           // FAIL: the first failing stage ("ssm:edges" when the case compares several effects)
  std::string message;         // FAIL: that stage and its figures; ERROR: the one-line error
  std::string details;         // FAIL: compare's table for the case (the JUnit failure's text)
  double seconds = 0.0;
  std::string page;            // the case's compare page, relative to the report folder ("" when none)
};

// Which cases ran: a share of the suite (`--shard I/N`, index 1..count), or all of it (1/1).
struct Shard {
  int index = 1;
  int count = 1;
};

struct SuiteResults {
  std::string suite;    // the folder of frame files, as given
  std::string subject;  // what the oracle was compared with ("the GL port (llvmpipe …)", "--shaders S", "--against A")
  Shard shard;
  int casesInSuite = 0;          // every case of the folder, in every shard
  std::vector<CaseResult> cases;  // sorted by name
};

// The cases of a folder: every regular file `*.json` directly in it, as case names (the file
// name without ".json"), sorted. MrrError when `dir` is no folder or holds no frame file.
std::vector<std::string> suiteCases(const std::string& dir);

// "I/N" with 1 <= I <= N: MrrError naming --shard otherwise.
Shard parseShard(const std::string& text);
// FNV-1a (64 bits) of the case's name: a case's shard depends on its name alone, so the shards
// partition the suite, and adding a case moves no other.
uint64_t caseHash(const std::string& name);
bool inShard(const std::string& name, const Shard& shard);

// The summary `mrr check` prints on stdout: one row per case (case, effect, method, verdict,
// first failing stage, time), each ERROR's message under the table, and a last line
// "PASS: …", "FAIL: …" or "ERROR: …".
std::string formatSummary(const SuiteResults& results);
// 0: every case passes; 1: one fails and none is an error; 2: one is an error.
int suiteExitCode(const SuiteResults& results);

// JUnit XML (the schema Jenkins, GitLab and GitHub's test reporters read): one testcase per
// case, classname "mrr.check.EFFECT"; a FAIL is a <failure> whose message names the stage and its
// figures, with compare's table as its text; an ERROR is an <error> with its message.
std::string junitXml(const SuiteResults& results);

// The results as JSON ({"mrr_check": 1, …}) and back; MrrError naming `source` for a file that
// is not one.
nlohmann::json resultsJson(const SuiteResults& results);
SuiteResults resultsFromJson(const nlohmann::json& json, const std::string& source);

// Joins the results of shards of one suite: every case of each, sorted by name. MrrError when
// they are not one suite's (different shard counts or suite sizes), when a shard is missing or
// given twice, or when two hold the same case.
SuiteResults mergeResults(const std::vector<SuiteResults>& parts, const std::vector<std::string>& sources);

// DIR/index.html: every case with its verdict, linking its compare page where DIR holds it
// (DIR/CASE/index.html). Made by the report program (compare/report/templates/check.html.j2);
// needs requireReportPython().
void writeSuiteIndex(const std::string& dir, const SuiteResults& results);

}  // namespace mrr
