#include "inertial/report/study_report.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace inertial {
namespace {

namespace fs = std::filesystem;

constexpr int kBodies = 20;
constexpr int kMethodNames = 4;
const std::array<const char*, kMethodNames> kNames = {"linear", "eigenvalue", "exponential", "log_cholesky"};

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// True if an executable `name` is on PATH.
bool OnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) dir = ".";
    const fs::path candidate = fs::path(dir) / name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0) return true;
  }
  return false;
}

// A fresh directory name under the system temporary directory, removed (recursively) on destruction.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("inertial_study_report_test_" + std::to_string(getpid()) + "_" + std::to_string(counter++));
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Histogram bin of one outcome, computed here from the documented bins: 1-5, ..., 46-50, failed.
int ExpectedBin(const MethodOutcome& m) {
  if (m.failed) return 10;
  return std::min(9, std::max(0, (m.iterations - 1) / 5));
}

class StudyReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    StudyOptions options;
    options.bodies = kBodies;
    options.seed = 3;
    options.threads = 2;
    result_ = std::make_unique<StudyResult>(RunStudy(options));
  }
  static void TearDownTestSuite() { result_.reset(); }
  static const StudyResult& result() { return *result_; }

 private:
  static std::unique_ptr<StudyResult> result_;
};
std::unique_ptr<StudyResult> StudyReportTest::result_;

TEST_F(StudyReportTest, RunHasTheRequestedBodies) {
  ASSERT_EQ(result().bodies.size(), static_cast<std::size_t>(kBodies));
  EXPECT_EQ(result().summary.bodies, kBodies);
}

TEST_F(StudyReportTest, JsonTopLevel) {
  const nlohmann::json j = StudyToJson(result());
  ASSERT_TRUE(j.is_object());
  ASSERT_TRUE(j.contains("bodies"));
  ASSERT_TRUE(j["bodies"].is_number_integer());
  EXPECT_EQ(j["bodies"].get<int>(), kBodies);
  ASSERT_TRUE(j.contains("seed"));
  EXPECT_EQ(j["seed"].get<std::uint64_t>(), 3u);
  ASSERT_TRUE(j.contains("settings"));
  EXPECT_EQ(j["settings"]["max_iterations"].get<int>(), 50);
  ASSERT_TRUE(j.contains("paper"));
  EXPECT_EQ(j["paper"]["nonphysical"].get<int>(), 151);
  EXPECT_EQ(j["paper"]["not_positive_definite"].get<int>(), 42);
  EXPECT_EQ(j["paper"]["bodies"].get<int>(), 1000);
}

// linear_ls counts are integers and agree with a recount from every body's consistency report.
TEST_F(StudyReportTest, JsonLinearLeastSquaresCountsMatchRecount) {
  int nonphysical = 0, negative_mass = 0, not_pd = 0, not_pd_com = 0, triangle = 0;
  for (const BodyOutcome& b : result().bodies) {
    const ConsistencyReport& r = b.linear_ls_report;
    if (r.fully_consistent()) continue;
    ++nonphysical;
    if (!r.mass_positive) ++negative_mass;
    if (!r.inertia_positive_definite_origin) ++not_pd;
    if (r.mass_positive && !r.inertia_positive_definite_com) ++not_pd_com;
    if (r.mass_positive && !r.triangle_inequalities) ++triangle;
  }
  const nlohmann::json j = StudyToJson(result());
  ASSERT_TRUE(j.contains("linear_ls"));
  const nlohmann::json& l = j["linear_ls"];
  for (const char* key : {"nonphysical", "negative_mass", "not_positive_definite", "not_positive_definite_com",
                          "triangle_violations"}) {
    ASSERT_TRUE(l.contains(key)) << key;
    EXPECT_TRUE(l[key].is_number_integer()) << key << " = " << l[key];
  }
  EXPECT_EQ(l["nonphysical"].get<int>(), nonphysical);
  EXPECT_EQ(l["negative_mass"].get<int>(), negative_mass);
  EXPECT_EQ(l["not_positive_definite"].get<int>(), not_pd);
  EXPECT_EQ(l["not_positive_definite_com"].get<int>(), not_pd_com);
  EXPECT_EQ(l["triangle_violations"].get<int>(), triangle);
  // A body with positive mass is nonphysical exactly when some condition at the COM fails; a
  // triangle violation is a subset of nonphysical.
  EXPECT_LE(triangle, nonphysical);
  EXPECT_LE(not_pd, nonphysical);
  EXPECT_GE(nonphysical, 0);
}

TEST_F(StudyReportTest, JsonHasExactlyTheFourMethods) {
  const nlohmann::json j = StudyToJson(result());
  ASSERT_TRUE(j.contains("methods"));
  ASSERT_TRUE(j["methods"].is_object());
  std::set<std::string> keys;
  for (auto it = j["methods"].begin(); it != j["methods"].end(); ++it) keys.insert(it.key());
  EXPECT_EQ(keys, (std::set<std::string>{"linear", "eigenvalue", "exponential", "log_cholesky"}));
  for (int k = 0; k < kMethodNames; ++k) EXPECT_EQ(StudyMethodName(k), kNames[k]);
}

TEST_F(StudyReportTest, JsonMethodIterationsFailuresAndTiming) {
  const nlohmann::json j = StudyToJson(result());
  for (int k = 0; k < kMethodNames; ++k) {
    SCOPED_TRACE(kNames[k]);
    const nlohmann::json& m = j["methods"][kNames[k]];
    ASSERT_TRUE(m.contains("iterations"));
    ASSERT_TRUE(m["iterations"].is_array());
    ASSERT_EQ(m["iterations"].size(), static_cast<std::size_t>(kBodies));
    int failures = 0, max_iteration_stops = 0;
    for (int i = 0; i < kBodies; ++i) {
      const MethodOutcome& outcome = result().bodies[i].methods[k];
      ASSERT_TRUE(m["iterations"][i].is_number_integer());
      EXPECT_EQ(m["iterations"][i].get<int>(), outcome.iterations) << "body " << i;
      EXPECT_GE(outcome.iterations, 0);
      EXPECT_LE(outcome.iterations, 50);
      if (outcome.failed) ++failures;
      if (outcome.reason == StopReason::kMaxIterations) ++max_iteration_stops;
    }
    ASSERT_TRUE(m["failures"].is_number_integer());
    EXPECT_EQ(m["failures"].get<int>(), failures);
    EXPECT_EQ(m["max_iteration_stops"].get<int>(), max_iteration_stops);
    ASSERT_TRUE(m["seconds_per_iteration"].is_number());
    EXPECT_GT(m["seconds_per_iteration"].get<double>(), 0.0);
    EXPECT_LT(m["seconds_per_iteration"].get<double>(), 1.0);  // a 10-parameter LM step, not a second
  }
}

TEST_F(StudyReportTest, JsonHistogramsMatchTheDocumentedBinsAndSumToBodies) {
  const nlohmann::json j = StudyToJson(result());
  for (int k = 0; k < kMethodNames; ++k) {
    SCOPED_TRACE(kNames[k]);
    const nlohmann::json& h = j["methods"][kNames[k]]["histogram"];
    ASSERT_TRUE(h.is_array());
    ASSERT_EQ(h.size(), 11u);  // 1-5, ..., 46-50, failed
    std::vector<int> expected(11, 0);
    for (const BodyOutcome& b : result().bodies) ++expected[ExpectedBin(b.methods[k])];
    int sum = 0;
    for (std::size_t i = 0; i < h.size(); ++i) {
      EXPECT_EQ(h[i].get<int>(), expected[i]) << "bin " << i;
      sum += h[i].get<int>();
    }
    EXPECT_EQ(sum, kBodies);
    EXPECT_EQ(h[10].get<int>(), j["methods"][kNames[k]]["failures"].get<int>());
  }
}

TEST_F(StudyReportTest, TableShowsThePapersFiguresAndThisRunsCounts) {
  const std::string table = StudyTable(result());
  EXPECT_TRUE(Contains(table, "151")) << table;
  EXPECT_TRUE(Contains(table, "42")) << table;
  EXPECT_TRUE(Contains(table, std::to_string(kBodies) + " random bodies")) << table;
  EXPECT_TRUE(Contains(table, "seed 3")) << table;

  const StudySummary& s = result().summary;
  std::istringstream lines(table);
  std::string line;
  bool saw_nonphysical = false, saw_triangle = false, saw_not_pd = false;
  std::array<bool, kMethodNames> saw_method{};
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    if (Contains(line, "not physically consistent")) {
      saw_nonphysical = true;
      // "  not physically consistent   N (x.y %)   151 (15.1 %)"
      const std::string after = line.substr(line.find("consistent") + 10);
      std::istringstream rest(after);
      int n = -1;
      rest >> n;
      EXPECT_EQ(n, s.nonphysical) << line;
    }
    if (Contains(line, "triangle inequality violated")) {
      saw_triangle = true;
      const std::string after = line.substr(line.find("(at COM)") + 8);
      std::istringstream rest(after);
      int n = -1;
      rest >> n;
      EXPECT_EQ(n, s.triangle_violations) << line;
    }
    if (Contains(line, "I (about origin) not positive definite")) {
      saw_not_pd = true;
      const std::string after = line.substr(line.find("definite") + 8);
      std::istringstream rest(after);
      int n = -1, paper = -1;
      rest >> n >> paper;
      EXPECT_EQ(n, s.not_positive_definite) << line;
      EXPECT_EQ(paper, 42) << line;
    }
    // Method rows: "  <name>  <failures>  <median its> ... histogram | failed".
    std::string first;
    words >> first;
    for (int k = 0; k < kMethodNames; ++k) {
      if (first == kNames[k] && line.rfind("  ", 0) == 0) {
        saw_method[k] = true;
        int failures = -1;
        words >> failures;
        EXPECT_EQ(failures, s.methods[k].failures) << line;
        // The last number after '|' is the failed bin.
        const std::size_t bar = line.rfind('|');
        ASSERT_NE(bar, std::string::npos) << line;
        EXPECT_EQ(std::stoi(line.substr(bar + 1)), s.methods[k].failures) << line;
      }
    }
  }
  EXPECT_TRUE(saw_nonphysical) << table;
  EXPECT_TRUE(saw_triangle) << table;
  EXPECT_TRUE(saw_not_pd) << table;
  for (int k = 0; k < kMethodNames; ++k) EXPECT_TRUE(saw_method[k]) << kNames[k] << "\n" << table;
}

TEST_F(StudyReportTest, WriteStudyReportCreatesAllFiles) {
  if (!OnPath("gnuplot")) GTEST_SKIP() << "gnuplot is not on PATH: WriteStudyReport cannot draw fig1.png";
  const TempDir tmp;
  // A directory that does not exist yet, two levels deep, with a space in its name.
  const fs::path dir = tmp.path() / "report dir" / "nested";
  ASSERT_FALSE(fs::exists(dir));
  ASSERT_NO_THROW(WriteStudyReport(result(), dir.string()));
  ASSERT_TRUE(fs::is_directory(dir));

  // fig1.png: a real PNG.
  const fs::path png = dir / "fig1.png";
  ASSERT_TRUE(fs::is_regular_file(png));
  EXPECT_GT(fs::file_size(png), 1000u);
  const std::string bytes = ReadFile(png);
  ASSERT_GE(bytes.size(), 8u);
  const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(static_cast<unsigned char>(bytes[i]), signature[i]) << "byte " << i;
  EXPECT_TRUE(fs::is_regular_file(dir / "fig1.gp"));

  // table.txt: the table.
  ASSERT_TRUE(fs::is_regular_file(dir / "table.txt"));
  EXPECT_EQ(ReadFile(dir / "table.txt"), StudyTable(result()));

  // study.json: parseable, and the same document as StudyToJson.
  ASSERT_TRUE(fs::is_regular_file(dir / "study.json"));
  nlohmann::json parsed;
  ASSERT_NO_THROW(parsed = nlohmann::json::parse(ReadFile(dir / "study.json")));
  const nlohmann::json expected = StudyToJson(result());
  EXPECT_EQ(parsed["bodies"], expected["bodies"]);
  EXPECT_EQ(parsed, expected);

  // iterations.dat: one row per bin (label + four counts), columns sum to the number of bodies.
  ASSERT_TRUE(fs::is_regular_file(dir / "iterations.dat"));
  std::istringstream dat(ReadFile(dir / "iterations.dat"));
  std::string line;
  std::vector<std::vector<int>> rows;
  std::vector<std::string> labels;
  while (std::getline(dat, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string label;
    words >> label;
    labels.push_back(label);
    std::vector<int> counts(kMethodNames, -1);
    for (int k = 0; k < kMethodNames; ++k) words >> counts[k];
    EXPECT_FALSE(words.fail()) << line;
    rows.push_back(counts);
  }
  ASSERT_EQ(rows.size(), 11u);
  EXPECT_EQ(labels.front(), "\"1-5\"");
  EXPECT_EQ(labels[9], "\"46-50\"");
  EXPECT_EQ(labels.back(), "\"failed\"");
  for (int k = 0; k < kMethodNames; ++k) {
    int sum = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      EXPECT_EQ(rows[i][k], expected["methods"][kNames[k]]["histogram"][i].get<int>()) << kNames[k] << " bin " << i;
      sum += rows[i][k];
    }
    EXPECT_EQ(sum, kBodies) << kNames[k];
  }
}

TEST_F(StudyReportTest, WriteStudyReportOverwritesAnExistingDirectory) {
  if (!OnPath("gnuplot")) GTEST_SKIP() << "gnuplot is not on PATH: WriteStudyReport cannot draw fig1.png";
  const TempDir tmp;
  fs::create_directories(tmp.path());
  { std::ofstream(tmp.path() / "table.txt") << "stale"; }
  ASSERT_NO_THROW(WriteStudyReport(result(), tmp.path().string()));
  EXPECT_EQ(ReadFile(tmp.path() / "table.txt"), StudyTable(result()));
}

TEST_F(StudyReportTest, DirectoryThatCannotBeCreatedThrowsNamingThePath) {
  const TempDir tmp;
  fs::create_directories(tmp.path());
  const fs::path file = tmp.path() / "a_regular_file";
  { std::ofstream(file) << "not a directory\n"; }
  const fs::path bad = file / "report";
  try {
    WriteStudyReport(result(), bad.string());
    FAIL() << "no exception for " << bad;
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(Contains(e.what(), bad.string())) << e.what();
  }
  EXPECT_FALSE(fs::exists(bad));
  // The regular file is untouched.
  EXPECT_EQ(ReadFile(file), "not a directory\n");
}

}  // namespace
}  // namespace inertial
