// Running the `fairspline` command from tests: a scratch directory per test, stdin from a
// string, stdout/stderr captured, the exit code. Shared by the CLI, batch and error-catalog
// tests.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace fairspline::testing {

struct CliRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// `s` in single quotes for /bin/sh.
inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// A test with its own scratch directory (kept when the test fails) and a runner for a command.
class CommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("fairspline-" + std::string(info->test_suite_name()) + "-" + info->name() + "-" +
            std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) std::filesystem::remove_all(dir_);
  }

  /// Runs `program args` (args already shell-quoted where needed) with optional stdin text.
  CliRun run_program(const std::string& program, const std::string& args,
                     const std::optional<std::string>& stdin_text = std::nullopt) {
    std::string cmd = shell_quote(program) + " " + args;
    if (stdin_text) {
      const std::filesystem::path in = dir_ / "stdin.txt";
      std::ofstream(in, std::ios::binary) << *stdin_text;
      cmd += " <" + shell_quote(in.string());
    } else {
      cmd += " </dev/null";
    }
    cmd += " >" + shell_quote((dir_ / "out.txt").string()) + " 2>" +
           shell_quote((dir_ / "err.txt").string());
    const int status = std::system(cmd.c_str());
    CliRun r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir_ / "out.txt");
    r.err = slurp(dir_ / "err.txt");
    return r;
  }

  /// Writes `content` to a file in the scratch directory and returns its path.
  std::filesystem::path file(const std::string& name, const std::string& content) {
    const std::filesystem::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }

  std::filesystem::path dir_;
};

}  // namespace fairspline::testing
