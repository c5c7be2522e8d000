// What `mrr check` does without rendering (compare/suite/suite.h): the cases of a folder,
// shards, the summary, JUnit XML, the results as JSON and merging shards' results.
#include "compare/suite/suite.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "common/error.h"
#include "tests/test_support.h"

namespace mrr {
namespace {
namespace fs = std::filesystem;

CaseResult make(const std::string& name, const std::string& verdict, const std::string& effect = "ssao") {
  CaseResult c;
  c.name = name;
  c.effect = effect;
  c.method = "mrr";
  c.verdict = verdict;
  c.seconds = 0.25;
  if (verdict == "FAIL") {
    c.stage = "raw.L0";
    c.message = "first failing stage raw.L0: ssao.same_input max|d| 0.03  rms 0.026  over 78% of 2304";
    c.details = "stage  verdict <table> & more\nFAIL: first failing stage raw.L0\n";
  }
  if (verdict == "ERROR") c.message = "frame file x.json: not a JSON object";
  return c;
}

std::vector<std::string> names(int n) {
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i) out.push_back("case-" + std::to_string(i));
  return out;
}

TEST(Suite, FnvHashIsTheStandardOne) {
  EXPECT_EQ(caseHash(""), 14695981039346656037ull);
  EXPECT_EQ(caseHash("a"), 0xaf63dc4c8601ec8cull);  // FNV-1a 64 test vector
  EXPECT_EQ(caseHash("foobar"), 0x85944171f73967e8ull);
}

// Every case lands in exactly one shard, and the shards are not all empty.
TEST(Suite, ShardsPartitionTheCases) {
  for (int count : {1, 2, 3, 7}) {
    std::vector<int> sizes(static_cast<size_t>(count));
    for (const std::string& n : names(200)) {
      int in = 0;
      for (int i = 1; i <= count; ++i)
        if (inShard(n, {i, count})) {
          ++in;
          ++sizes[static_cast<size_t>(i - 1)];
        }
      EXPECT_EQ(in, 1) << n << " in " << count << " shards";
    }
    for (int s : sizes) EXPECT_GT(s, 200 / count / 3) << count;  // spread, roughly
  }
}

// A case's shard depends on its name alone: adding cases moves none of the others.
TEST(Suite, AddingCasesMovesNoOther) {
  std::vector<int> before;
  for (const std::string& n : names(50))
    for (int i = 1; i <= 4; ++i)
      if (inShard(n, {i, 4})) before.push_back(i);
  const std::vector<std::string> more = names(80);  // the first 50 and 30 new
  for (size_t k = 0; k < 50; ++k)
    for (int i = 1; i <= 4; ++i)
      if (inShard(more[k], {i, 4})) EXPECT_EQ(before[k], i) << more[k];
}

TEST(Suite, ParseShard) {
  EXPECT_EQ(parseShard("2/4").index, 2);
  EXPECT_EQ(parseShard("2/4").count, 4);
  for (const char* bad : {"0/2", "3/2", "1/0", "1-2", "1/2x", "", "a/b"}) EXPECT_THROW(parseShard(bad), MrrError) << bad;
}

TEST(Suite, CasesAreTheFolderJsonFilesSorted) {
  const std::string dir = test::scratchDir();
  for (const char* f : {"b.json", "a.json", "notes.txt", "c.JSON"}) std::ofstream(fs::path(dir) / f) << "{}";
  fs::create_directories(fs::path(dir) / "d.json");  // a folder is no case
  EXPECT_EQ(suiteCases(dir), (std::vector<std::string>{"a", "b"}));
  EXPECT_THROW(suiteCases((fs::path(dir) / "missing").string()), MrrError);
  const std::string empty = (fs::path(dir) / "empty").string();
  fs::create_directories(empty);
  EXPECT_THROW(suiteCases(empty), MrrError);
}

TEST(Suite, SummaryAndExitCode) {
  SuiteResults r;
  r.suite = "frames";
  r.casesInSuite = 3;
  r.cases = {make("a", "PASS"), make("b", "PASS", "ssm"), make("c", "PASS", "ssgi")};
  std::string s = formatSummary(r);
  EXPECT_EQ(s.substr(0, s.find('\n')), "case  effect  method  verdict  first failing stage    time");
  EXPECT_NE(s.find("\nb     ssm     mrr     PASS     -                    0.25 s\n"), std::string::npos) << s;
  EXPECT_NE(s.find("PASS: all 3 cases\n"), std::string::npos) << s;
  EXPECT_EQ(suiteExitCode(r), 0);
  r.cases[1] = make("b", "FAIL");
  s = formatSummary(r);
  EXPECT_NE(s.find("b: FAIL: first failing stage raw.L0: ssao.same_input"), std::string::npos) << s;
  EXPECT_NE(s.find("FAIL: 1 of 3 cases failed\n"), std::string::npos) << s;
  EXPECT_EQ(suiteExitCode(r), 1);
  r.cases[2] = make("c", "ERROR");
  s = formatSummary(r);
  EXPECT_NE(s.find("ERROR: 1 of 3 cases could not run; 1 failed\n"), std::string::npos) << s;
  EXPECT_EQ(suiteExitCode(r), 2);
}

TEST(Suite, JunitHasATestcasePerCaseEscaped) {
  SuiteResults r;
  r.suite = "frames";
  r.subject = "the GL port";
  r.casesInSuite = 3;
  r.cases = {make("a", "PASS"), make("b<&>", "FAIL", "ssm"), make("c", "ERROR", "-")};
  const std::string x = junitXml(r);
  EXPECT_EQ(x.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites ", 0), 0u) << x;
  EXPECT_NE(x.find("tests=\"3\" failures=\"1\" errors=\"1\""), std::string::npos) << x;
  EXPECT_NE(x.find("<testcase classname=\"mrr.check.ssao\" name=\"a\" time=\"0.250\"/>"), std::string::npos) << x;
  EXPECT_NE(x.find("<testcase classname=\"mrr.check.ssm\" name=\"b&lt;&amp;&gt;\""), std::string::npos) << x;
  EXPECT_NE(x.find("<failure message=\"first failing stage raw.L0: ssao.same_input max|d| 0.03  rms 0.026  over 78% of 2304\" "
                   "type=\"FAIL\">stage  verdict &lt;table&gt; &amp; more\n"),
            std::string::npos)
      << x;
  EXPECT_NE(x.find("<testcase classname=\"mrr.check\" name=\"c\""), std::string::npos) << x;
  EXPECT_NE(x.find("<error message=\"frame file x.json: not a JSON object\" type=\"ERROR\">"), std::string::npos) << x;
}

SuiteResults shardOf(const std::vector<CaseResult>& all, Shard s) {
  SuiteResults r;
  r.suite = "frames";
  r.subject = "the GL port";
  r.shard = s;
  r.casesInSuite = static_cast<int>(all.size());
  for (const CaseResult& c : all)
    if (inShard(c.name, s)) r.cases.push_back(c);
  return r;
}

// Shards' results through JSON and merged: the same summary as the whole suite.
TEST(Suite, MergedShardsGiveTheWholeSuite) {
  std::vector<CaseResult> all;
  for (const std::string& n : names(9)) all.push_back(make(n, n == "case-3" ? "FAIL" : n == "case-5" ? "ERROR" : "PASS"));
  SuiteResults whole = shardOf(all, {1, 1});
  std::vector<SuiteResults> parts;
  for (int i = 1; i <= 3; ++i) {
    const SuiteResults p = shardOf(all, {i, 3});
    parts.push_back(resultsFromJson(nlohmann::json::parse(resultsJson(p).dump()), "r" + std::to_string(i)));
  }
  const SuiteResults merged = mergeResults(parts, {"r1", "r2", "r3"});
  EXPECT_EQ(formatSummary(merged), formatSummary(whole));
  EXPECT_EQ(junitXml(merged), junitXml(whole));
  EXPECT_EQ(merged.cases[3].details, all[3].details);
  // A shard missing, given twice, or from another suite: refused.
  EXPECT_THROW(mergeResults({parts[0], parts[1]}, {"r1", "r2"}), MrrError);
  EXPECT_THROW(mergeResults({parts[0], parts[1], parts[1]}, {"r1", "r2", "r2b"}), MrrError);
  SuiteResults other = parts[2];
  other.casesInSuite = 10;
  EXPECT_THROW(mergeResults({parts[0], parts[1], other}, {"r1", "r2", "r3"}), MrrError);
  EXPECT_THROW(resultsFromJson(nlohmann::json::object(), "x.json"), MrrError);
  EXPECT_THROW(resultsFromJson({{"mrr_check", 1}, {"suite", "s"}}, "x.json"), MrrError);
}

}  // namespace
}  // namespace mrr
