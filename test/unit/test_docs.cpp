// The documentation keeps up with the source tree (IRAF_VO_SOURCE_DIR):
//   - every test program (test/unit/test_*.cpp, test/ros_unit/test_*.cpp, test/ros/*.test, test/fuzz/fuzz_*.cpp)
//     is listed in docs/testing.md, and every test program docs/testing.md names exists;
//   - README.md stays a short user page (<= 300 lines) and links the docs;
//   - the project's files speak of the software only: no development-history words (the word session or issue
//     followed by a number, or "this" + " branch") in any tracked file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
const fs::path kSource = IRAF_VO_SOURCE_DIR;

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool isWordChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

/// `name` occurs in `text` as a whole word (not as the prefix of test_features_fast when looking for test_features).
bool mentions(const std::string& text, const std::string& name) {
  for (size_t pos = text.find(name); pos != std::string::npos; pos = text.find(name, pos + 1)) {
    const bool left_ok = pos == 0 || !isWordChar(text[pos - 1]);
    const size_t end = pos + name.size();
    const bool right_ok = end >= text.size() || !isWordChar(text[end]);
    if (left_ok && right_ok) return true;
  }
  return false;
}

/// The names under which docs/testing.md lists the test programs: test_x for gtests, x.test for rostests,
/// fuzz_x for the libFuzzer targets.
std::vector<std::string> testPrograms() {
  std::vector<std::string> names;
  const auto collect = [&](const char* dir, const std::string& prefix, const std::string& ext, bool keep_ext) {
    if (!fs::is_directory(kSource / dir)) return;
    for (const auto& e : fs::directory_iterator(kSource / dir)) {
      const std::string file = e.path().filename().string();
      if (file.rfind(prefix, 0) != 0 || e.path().extension() != ext) continue;
      names.push_back(keep_ext ? file : e.path().stem().string());
    }
  };
  collect("test/unit", "test_", ".cpp", false);
  collect("test/ros_unit", "test_", ".cpp", false);
  collect("test/ros", "", ".test", true);
  collect("test/fuzz", "fuzz_", ".cpp", false);
  std::sort(names.begin(), names.end());
  return names;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// Files under version control (git ls-files); when the tree is not a git checkout, every regular file outside
/// the build folders and .git.
std::vector<fs::path> projectFiles() {
  std::vector<fs::path> files;
  const std::string cmd = "git -C '" + kSource.string() + "' ls-files -z 2>/dev/null";
  if (FILE* p = ::popen(cmd.c_str(), "r")) {
    std::string out;
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    const int rc = ::pclose(p);
    if (rc == 0) {
      for (size_t b = 0, e; b < out.size(); b = e + 1) {
        e = out.find('\0', b);
        if (e == std::string::npos) e = out.size();
        if (e > b) files.push_back(kSource / out.substr(b, e - b));
      }
      if (!files.empty()) return files;
    }
  }
  for (auto it = fs::recursive_directory_iterator(kSource); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().filename().string();
    if (it->is_directory() && (name == ".git" || name.rfind("build", 0) == 0)) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file()) files.push_back(it->path());
  }
  return files;
}

/// Development-history words: session(s) or issue followed by a number, and "this" + " branch" (case-insensitive).
/// Returns the first offending phrase in `text`, or "".
std::string historyWord(const std::string& text) {
  std::string low(text.size(), ' ');
  std::transform(text.begin(), text.end(), low.begin(), [](unsigned char c) { return std::tolower(c); });
  // End of "word[s] <digits>" starting at pos, or 0 when no number follows.
  const auto numberAfter = [&](size_t pos, const std::string& word) -> size_t {
    size_t i = pos + word.size();
    if (word == "session" && i < low.size() && low[i] == 's') ++i;
    if (i + 1 >= low.size() || low[i] != ' ' || !std::isdigit(static_cast<unsigned char>(low[i + 1]))) return 0;
    for (i += 1; i < low.size() && std::isdigit(static_cast<unsigned char>(low[i]));) ++i;
    return i;
  };
  for (const std::string word : {"session", "issue"}) {
    for (size_t pos = low.find(word); pos != std::string::npos; pos = low.find(word, pos + 1)) {
      if (const size_t end = numberAfter(pos, word)) return text.substr(pos, end - pos);
    }
  }
  const size_t pos = low.find("this " "branch");
  return pos == std::string::npos ? std::string() : text.substr(pos, 11);
}

TEST(Docs, EveryTestProgramIsListedInTesting) {
  const fs::path testing = kSource / "docs/testing.md";
  ASSERT_TRUE(fs::exists(testing)) << testing << " is missing";
  const std::string text = readFile(testing);
  const std::vector<std::string> programs = testPrograms();
  ASSERT_GT(programs.size(), 30u) << "test programs not found under " << kSource;
  std::vector<std::string> unlisted;
  for (const auto& name : programs) {
    if (!mentions(text, name)) unlisted.push_back(name);
  }
  EXPECT_TRUE(unlisted.empty()) << unlisted.size() << " of " << programs.size()
                                << " test programs are not listed in docs/testing.md: " << joined(unlisted);
}

TEST(Docs, EveryTestProgramListedInTestingExists) {
  const std::string text = readFile(kSource / "docs/testing.md");
  const std::vector<std::string> programs = testPrograms();
  const std::set<std::string> known(programs.begin(), programs.end());
  std::set<std::string> stale;
  for (const std::string prefix : {"test_", "fuzz_"}) {
    for (size_t pos = text.find(prefix); pos != std::string::npos; pos = text.find(prefix, pos + 1)) {
      if (pos > 0 && isWordChar(text[pos - 1])) continue;
      size_t end = pos;
      while (end < text.size() && isWordChar(text[end])) ++end;
      const std::string name = text.substr(pos, end - pos);
      // test_data.h, test_*.cpp and test_<x> patterns are not program names.
      if (end == pos + prefix.size() || (end < text.size() && (text[end] == '.' || text[end] == '*'))) continue;
      if (!known.count(name)) stale.insert(name);
    }
  }
  EXPECT_TRUE(stale.empty()) << "docs/testing.md names test programs that do not exist: "
                             << joined(std::vector<std::string>(stale.begin(), stale.end()));
}

TEST(Docs, ReadmeIsShortAndLinksTheDocs) {
  const fs::path readme = kSource / "README.md";
  ASSERT_TRUE(fs::exists(readme));
  const std::string text = readFile(readme);
  const long lines = std::count(text.begin(), text.end(), '\n');
  EXPECT_LE(lines, 300) << "README.md has " << lines << " lines: move reference material to docs/";
  for (const char* doc : {"docs/architecture.md", "docs/ros_interface.md", "docs/parameters.md", "docs/evaluation.md",
                          "docs/benchmarks.md", "docs/decisions.md", "docs/testing.md", "CHANGELOG.md"}) {
    EXPECT_NE(text.find(doc), std::string::npos) << "README.md does not link " << doc;
  }
}

TEST(Docs, NoDevelopmentHistoryWordsInTheProjectFiles) {
  std::vector<std::string> hits;
  for (const fs::path& file : projectFiles()) {
    if (!fs::is_regular_file(file) || file.extension() == ".png") continue;
    const std::string word = historyWord(readFile(file));
    if (!word.empty()) hits.push_back(fs::relative(file, kSource).string() + " (\"" + word + "\")");
  }
  EXPECT_TRUE(hits.empty()) << "files that speak of the development history instead of the software: "
                            << joined(hits);
}

TEST(Docs, HistoryWordsAreRecognized) {
  // The phrases are split so that this file does not contain them.
  EXPECT_EQ(historyWord("measured in Session " "9 on"), "Session " "9");
  EXPECT_EQ(historyWord("sessions " "5 and 6"), "sessions " "5");
  EXPECT_EQ(historyWord("as on This " "Branch"), "This " "Branch");
  EXPECT_EQ(historyWord("(issue " "11 step 5)"), "issue " "11");
  EXPECT_EQ(historyWord("TrackingSession owns the run rules; issues are filed"), "");
  EXPECT_TRUE(mentions("`test_features`, `test_features_fast`", "test_features"));
  EXPECT_FALSE(mentions("`test_features_fast`", "test_features"));
}

}  // namespace
