// End-to-end tests of `fairspline batch` (the real binary, as in cli_test.cpp).
#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "test_util.hpp"

#ifdef FAIRSPLINE_CLI

namespace {

namespace fs = std::filesystem;
using fairspline::testing::CliRun;
using fairspline::testing::slurp;
using nlohmann::json;

std::string quote(const std::string& s) {
  return fairspline::testing::shell_quote(s);
}

std::vector<json> parse_lines(const std::string& text) {
  std::vector<json> records;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) records.push_back(json::parse(line));
  return records;
}

/// A request line: a random walk of n points, compact JSON (doubles round-trip exactly).
json walk_request(std::size_t n, std::uint64_t seed) {
  json points = json::array();
  for (const fairspline::Point& p : fairspline::testing::random_walk(n, seed, 100)) {
    points.push_back({p.x, p.y});
  }
  return {{"points", points}};
}

class CliBatch : public fairspline::testing::CommandTest {
 protected:
  /// Runs the CLI with `args` (already shell-quoted), stdin from `stdin_text` or /dev/null,
  /// stdout and stderr to files (so stderr is not a terminal).
  CliRun run(const std::string& args, const std::optional<std::string>& stdin_text = std::nullopt) {
    return run_program(FAIRSPLINE_CLI, args, stdin_text);
  }

  /// Same, but stderr is a pseudo-terminal: err is what the terminal received.
  CliRun run_on_tty(const std::string& args) {
    const std::string cmd = command(args);
    CliRun r;
    const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
    if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0) {
      ADD_FAILURE() << "no pseudo-terminal";
      return r;
    }
    // The parent keeps the terminal side open until the child is done, so that reading the
    // master never sees a hang-up before the child has opened it.
    const int slave = ::open(::ptsname(master), O_RDWR | O_NOCTTY);
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::dup2(slave, STDERR_FILENO);
      ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    int status = 0;
    bool exited = false;
    char buf[4096];
    for (;;) {
      pollfd p{master, POLLIN, 0};
      if (::poll(&p, 1, exited ? 0 : 50) > 0 && (p.revents & POLLIN)) {
        const ssize_t n = ::read(master, buf, sizeof buf);
        if (n > 0) {
          r.err.append(buf, static_cast<std::size_t>(n));
          continue;
        }
      }
      if (exited) break;
      exited = ::waitpid(pid, &status, WNOHANG) == pid;
    }
    ::close(slave);
    ::close(master);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir_ / "out.txt");
    return r;
  }

 private:
  /// The shell command of run_on_tty: stdin from /dev/null, stdout to out.txt.
  std::string command(const std::string& args) {
    return quote(FAIRSPLINE_CLI) + " " + args + " </dev/null >" +
           quote((dir_ / "out.txt").string());
  }
};

/// ~200 lines of mixed requests: methods, sizes (3 to 150 points, so that lines take uneven
/// time), open and closed curves, and a failing line every 37 lines. Returns the text and
/// fills `requests` with each fitted line's request, by 1-based line number.
std::string mixed_lines(std::size_t count, std::vector<std::optional<json>>& requests) {
  const char* methods[] = {"jaklic-zagar", "li-strain", "quasi-elastic", "li-combined", ""};
  std::string text;
  requests.assign(count + 1, std::nullopt);
  for (std::size_t line = 1; line <= count; ++line) {
    if (line % 23 == 0) {
      text += line % 2 ? "\n" : "# a comment line\n";
      continue;
    }
    const std::size_t n = line % 50 == 1 ? 150 : 3 + line % 17;
    json request = walk_request(n, line);
    if (line % 37 == 0) request["points"][1] = request["points"][0];  // repeated point
    const std::string method = methods[line % 5];
    if (!method.empty()) request["method"] = method;
    if (line % 4 == 0 && method != "li-combined") request["closed"] = true;
    text += request.dump() + "\n";
    requests[line] = request;
  }
  return text;
}

TEST_F(CliBatch, KeepsInputOrderWithSeveralThreads) {
  std::vector<std::optional<json>> requests;
  const fs::path in = file("mixed.jsonl", mixed_lines(200, requests));
  const CliRun r = run("batch " + quote(in.string()) + " --threads 2 --report none");
  const std::vector<json> records = parse_lines(r.out);
  std::size_t expected = 0, failures = 0;
  for (const auto& q : requests) expected += q.has_value();
  ASSERT_EQ(records.size(), expected);
  std::size_t k = 0;
  for (std::size_t line = 1; line < requests.size(); ++line) {
    if (!requests[line]) continue;
    const json& rec = records[k++];
    ASSERT_EQ(rec["line"], line);
    if (line % 37 == 0) {
      ++failures;
      EXPECT_EQ(rec["error"]["code"], "repeated_point") << line;
      EXPECT_EQ(rec["error"]["index"], 1) << line;
      continue;
    }
    // The record is the fit of this line's curve: same points, one segment per span.
    ASSERT_FALSE(rec.contains("error")) << rec.dump();
    EXPECT_EQ(rec["points"], (*requests[line])["points"]) << line;
    const std::size_t n = (*requests[line])["points"].size();
    const bool closed = requests[line]->value("closed", false);
    EXPECT_EQ(rec["segments"].size(), closed ? n : n - 1) << line;
    EXPECT_EQ(rec["method"], requests[line]->value("method", "quasi-elastic")) << line;
    EXPECT_FALSE(rec.contains("report"));  // --report none
  }
  EXPECT_EQ(failures, 5u);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "fairspline batch: 5 of " + std::to_string(expected) + " records failed\n");
}

TEST_F(CliBatch, SameBytesForAnyThreadCount) {
  std::vector<std::optional<json>> requests;
  const fs::path in = file("mixed.jsonl", mixed_lines(240, requests));
  const CliRun one = run("batch " + quote(in.string()) + " --threads 1");
  ASSERT_EQ(one.exit_code, 1) << one.err;  // the repeated-point lines
  ASSERT_GT(one.out.size(), 100'000u);
  for (const std::string threads : {"2", "4", "0"}) {
    const CliRun other = run("batch " + quote(in.string()) + " --threads " + threads);
    EXPECT_EQ(other.exit_code, 1);
    EXPECT_TRUE(other.out == one.out) << "--threads " << threads << " differs from --threads 1";
    EXPECT_EQ(other.err, one.err);
  }
}

TEST_F(CliBatch, ErrorRecordsNameLineCodeAndIndex) {
  const std::string good = walk_request(6, 1).dump();
  const std::string text = good + "\n" +                                      // 1
                           "{\"points\": [[0,0],[1,1],[2,0]\n" +              // 2: malformed
                           "{\"points\": [[0,0],[1,1],[1e999,2],[3,0]]}\n" +  // 3: overflows to inf
                           "{\"points\": [[0,0],[NaN,1],[2,0]]}\n" +          // 4: NaN is not JSON
                           good + "\n" +                                      // 5
                           "{\"points\": [[0,0],[1,1],[2,0]], \"method\": \"nope\"}\n" +  // 6
                           "{\"points\": [[0,0]]}\n";                                     // 7
  const CliRun r = run("batch " + quote(file("errors.jsonl", text).string()) + " --threads 2");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "fairspline batch: 5 of 7 records failed\n");
  const std::vector<json> records = parse_lines(r.out);
  ASSERT_EQ(records.size(), 7u);
  for (std::size_t i = 0; i < records.size(); ++i) EXPECT_EQ(records[i]["line"], i + 1);
  EXPECT_FALSE(records[0].contains("error"));
  EXPECT_FALSE(records[4].contains("error"));
  EXPECT_EQ(records[0]["method"], "quasi-elastic");

  // A JSON syntax error names the line of the input, in the message and as the index.
  EXPECT_EQ(records[1]["error"]["code"], "parse_error");
  EXPECT_EQ(records[1]["error"]["index"], 2);
  EXPECT_EQ(records[1]["error"]["message"].get<std::string>().rfind("invalid JSON at line 2, ", 0),
            0u)
      << records[1].dump();
  EXPECT_EQ(records[1]["method"], nullptr);  // unknown: the line could not be read
  // 1e999 is not a finite double: non_finite at point 2.
  EXPECT_EQ(records[2]["error"]["code"], "non_finite");
  EXPECT_EQ(records[2]["error"]["index"], 2);
  EXPECT_NE(records[2]["error"]["message"].get<std::string>().find("points[2]"), std::string::npos);
  EXPECT_EQ(records[3]["error"]["code"], "parse_error");
  EXPECT_EQ(records[3]["error"]["index"], 4);
  EXPECT_EQ(records[5]["error"]["code"], "unknown_method");
  EXPECT_EQ(records[5]["error"]["index"], nullptr);
  EXPECT_EQ(records[5]["method"], "nope");
  EXPECT_EQ(records[6]["error"]["code"], "too_few_points");
  EXPECT_EQ(records[6]["method"], "quasi-elastic");
  // Exactly the three keys of an error record.
  EXPECT_EQ(records[2].size(), 3u);
  EXPECT_EQ(records[2]["error"].size(), 3u);
}

TEST_F(CliBatch, BlankAndCommentLinesAreSkippedButCounted) {
  const std::string a = walk_request(5, 3).dump(), b = walk_request(7, 4).dump();
  const std::string text =
      "# curves\n\n" + a + "\r\n   \n\t# indented comment\n" + b;  // CRLF, no final newline
  const CliRun r = run("batch " + quote(file("blank.jsonl", text).string()) + " --report none");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const std::vector<json> records = parse_lines(r.out);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0]["line"], 3);
  EXPECT_EQ(records[0]["segments"].size(), 4u);
  EXPECT_EQ(records[1]["line"], 6);
  EXPECT_EQ(records[1]["segments"].size(), 6u);
  // Nothing to fit: no output, success.
  const CliRun empty = run("batch " + quote(file("empty.jsonl", "# nothing\n\n").string()));
  EXPECT_EQ(empty.exit_code, 0);
  EXPECT_EQ(empty.out, "");
  EXPECT_EQ(empty.err, "");
}

TEST_F(CliBatch, RepeatedMethodFitsEveryLineWithEachInOrder) {
  json with_method = walk_request(8, 5);
  with_method["method"] = "li-combined";  // -m overrides it
  const std::string text = walk_request(6, 6).dump() + "\n" + with_method.dump() + "\nnot json\n";
  const CliRun r = run("batch " + quote(file("m.jsonl", text).string()) +
                       " -m jaklic-zagar -m li-strain --report none --threads 2");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "fairspline batch: 2 of 6 records failed\n");
  const std::vector<json> records = parse_lines(r.out);
  ASSERT_EQ(records.size(), 6u);
  const int lines[] = {1, 1, 2, 2, 3, 3};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(records[i]["line"], lines[i]);
    EXPECT_EQ(records[i]["method"], i % 2 == 0 ? "jaklic-zagar" : "li-strain");
  }
  EXPECT_EQ(records[2]["segments"].size(), 7u);
  // The two methods give different curves through the same points.
  EXPECT_EQ(records[0]["points"], records[1]["points"]);
  EXPECT_NE(records[0]["segments"], records[1]["segments"]);
  EXPECT_EQ(records[4]["error"]["code"], "parse_error");
  EXPECT_EQ(records[5]["error"]["code"], "parse_error");
}

TEST_F(CliBatch, ReadsStandardInput) {
  std::vector<std::optional<json>> requests;
  const std::string text = mixed_lines(60, requests);
  const CliRun from_file = run("batch " + quote(file("in.jsonl", text).string()));
  const CliRun from_stdin = run("batch", text);
  const CliRun from_dash = run("batch - --threads 1", text);
  EXPECT_EQ(from_file.exit_code, 1);
  EXPECT_EQ(from_stdin.exit_code, 1);
  EXPECT_EQ(from_dash.exit_code, 1);
  EXPECT_GT(from_file.out.size(), 10'000u);
  EXPECT_TRUE(from_stdin.out == from_file.out);
  EXPECT_TRUE(from_dash.out == from_file.out);
  EXPECT_EQ(parse_lines(from_stdin.out).size(), 58u);  // lines 23 and 46 are skipped
}

TEST_F(CliBatch, ReadsAheadAcrossTheBlocksOfAFile) {
  // 9000 lines are three blocks of 4096. From a regular file the next block is read while this
  // one is fitted; from a pipe it is read after. Both give the same records, in order, with the
  // skipped and failing lines where they are, on one thread or two.
  std::string text;
  std::size_t expected = 0;
  for (std::size_t line = 1; line <= 9000; ++line) {
    if (line % 1000 == 0) {
      text += line % 2000 == 0 ? "# comment\n" : "\n";
      continue;
    }
    json request = walk_request(3 + line % 4, line);
    if (line % 997 == 0) request["points"][1] = request["points"][0];  // repeated point
    text += request.dump() + "\n";
    ++expected;
  }
  const fs::path in = file("blocks.jsonl", text);
  const std::string args = " -m jaklic-zagar --report none";
  const CliRun from_file = run("batch " + quote(in.string()) + args + " --threads 2");
  const CliRun one = run("batch " + quote(in.string()) + args + " --threads 1");
  const CliRun piped =
      run_program("sh", "-c " + quote("cat " + quote(in.string()) + " | " + quote(FAIRSPLINE_CLI) +
                                      " batch -" + args + " --threads 2"));
  EXPECT_EQ(from_file.exit_code, 1);
  EXPECT_EQ(from_file.err,
            "fairspline batch: 9 of " + std::to_string(expected) + " records failed\n");
  const std::vector<json> records = parse_lines(from_file.out);
  ASSERT_EQ(records.size(), expected);
  std::size_t k = 0;
  for (std::size_t line = 1; line <= 9000; ++line) {
    if (line % 1000 == 0) continue;
    ASSERT_EQ(records[k]["line"], line);
    EXPECT_EQ(records[k].contains("error"), line % 997 == 0) << line;
    ++k;
  }
  EXPECT_TRUE(one.out == from_file.out);
  EXPECT_EQ(piped.exit_code, 1);
  EXPECT_TRUE(piped.out == from_file.out);
}

TEST_F(CliBatch, RecordsEqualFitOutput) {
  // Each method on one curve: `fit` of the request file and the batch record agree exactly
  // (doubles compared after parsing both), apart from the added "line": both are
  // io::write_json, the batch record with "line" as an extra member.
  std::string text;
  std::vector<json> requests;
  for (const std::string method : {"jaklic-zagar", "li-strain", "li-combined", "quasi-elastic",
                                   "yong-cheng", "kozak-krajnc"}) {
    json request = walk_request(method == "kozak-krajnc" ? 10 : 9, requests.size() + 10);
    request["method"] = method;
    if (method == "li-strain") request["closed"] = true;
    if (method == "yong-cheng") request["options"] = {{"tangents_from", "jaklic-zagar"}};
    requests.push_back(request);
    text += request.dump() + "\n";
  }
  for (const std::string report : {"basic", "full"}) {
    const CliRun batch = run("batch " + quote(file("in.jsonl", text).string()) + " --report " +
                             report + " -o " + quote((dir_ / "batch.jsonl").string()));
    ASSERT_EQ(batch.exit_code, 0) << batch.err;
    EXPECT_EQ(batch.out, "");  // written to -o
    const std::string batch_text = slurp(dir_ / "batch.jsonl");
    std::vector<json> records = parse_lines(batch_text);
    ASSERT_EQ(records.size(), requests.size());
    std::vector<std::string> raw;
    std::istringstream lines(batch_text);
    for (std::string l; std::getline(lines, l);) raw.push_back(l + "\n");
    for (std::size_t i = 0; i < requests.size(); ++i) {
      const fs::path one = file("one.json", requests[i].dump());
      const CliRun fit = run("fit " + quote(one.string()) + " --report " + report);
      ASSERT_EQ(fit.exit_code, 0) << fit.err;
      const json expected = json::parse(fit.out);
      json& got = records[i];
      EXPECT_EQ(got["line"], i + 1);
      ASSERT_EQ(got["segments"].size(), expected["segments"].size());
      for (std::size_t s = 0; s < expected["segments"].size(); ++s) {
        for (int k = 0; k < 4; ++k) {
          EXPECT_EQ(got["segments"][s]["bezier"][k][0].get<double>(),
                    expected["segments"][s]["bezier"][k][0].get<double>());
          EXPECT_EQ(got["segments"][s]["bezier"][k][1].get<double>(),
                    expected["segments"][s]["bezier"][k][1].get<double>());
        }
      }
      got.erase("line");
      EXPECT_EQ(got, expected) << requests[i]["method"];
      // Byte for byte too: the record is fit's output with "line" inserted in key order.
      const std::string line_key = ",\"line\":" + std::to_string(i + 1);
      const auto at = raw[i].find(line_key);
      ASSERT_NE(at, std::string::npos) << raw[i];
      EXPECT_TRUE(raw[i].substr(0, at) + raw[i].substr(at + line_key.size()) == fit.out)
          << requests[i]["method"] << "\n"
          << raw[i] << fit.out;
      EXPECT_TRUE(expected.contains("report"));
    }
  }
  // The default report level of batch is basic: bending energy and length, not the curvature
  // variation, the per-piece reports or the intersections.
  const CliRun dflt = run("batch", requests[0].dump());
  ASSERT_EQ(dflt.exit_code, 0) << dflt.err;
  const json rec = json::parse(dflt.out);
  EXPECT_TRUE(rec["report"]["linearized_energy"].is_number());
  EXPECT_TRUE(rec["report"]["bending_energy"].is_number());
  EXPECT_TRUE(rec["report"]["length"].is_number());
  EXPECT_TRUE(rec["report"]["curvature_variation_energy"].is_null());
  EXPECT_FALSE(rec["report"].contains("segment_reports"));
  EXPECT_FALSE(rec["report"].contains("intersections"));
}

TEST_F(CliBatch, ProgressOnlyOnATerminal) {
  std::string text;
  for (std::uint64_t i = 0; i < 300; ++i) text += walk_request(12, i).dump() + "\n";
  const fs::path in = file("in.jsonl", text);
  const std::string args = "batch " + quote(in.string()) + " --report none --threads 2";
  // stderr a file: not one byte of progress.
  const CliRun plain = run(args);
  ASSERT_EQ(plain.exit_code, 0);
  EXPECT_EQ(plain.err, "");
  EXPECT_EQ(parse_lines(plain.out).size(), 300u);
  // stderr a terminal: the progress line, ending with the totals.
  const CliRun tty = run_on_tty(args);
  ASSERT_EQ(tty.exit_code, 0) << tty.err;
  EXPECT_TRUE(tty.out == plain.out);
  EXPECT_NE(tty.err.find("\rfairspline batch: 300 records in "), std::string::npos) << tty.err;
  EXPECT_NE(tty.err.find(" records/s)"), std::string::npos) << tty.err;
  // --quiet: nothing, even on a terminal.
  const CliRun quiet = run_on_tty(args + " --quiet");
  ASSERT_EQ(quiet.exit_code, 0);
  EXPECT_EQ(quiet.err, "");
  EXPECT_TRUE(quiet.out == plain.out);
}

/// Reads from `fd` into `text` until it holds `lines` complete lines; false after `seconds`
/// without them, or at the end of the output.
bool read_lines(int fd, std::string& text, std::size_t lines, int seconds) {
  for (int waited = 0;
       static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) < lines;) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 100) == 0) {
      if (++waited > seconds * 10) return false;
      continue;
    }
    char buf[4096];
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n <= 0) return false;
    text.append(buf, static_cast<std::size_t>(n));
  }
  return true;
}

TEST_F(CliBatch, StreamsRecordsWhileTheInputIsStillOpen) {
  // A producer that sends one line and waits: the record must come out before more input (or
  // the end of it) arrives, instead of waiting for a whole block. The 60 s is a guard against
  // hanging, not a timing check.
  int in[2], out[2];
  ASSERT_EQ(::pipe(in), 0);
  ASSERT_EQ(::pipe(out), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(in[0], STDIN_FILENO);
    ::dup2(out[1], STDOUT_FILENO);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDERR_FILENO);
    for (int fd : {in[0], in[1], out[0], out[1], null}) ::close(fd);
    ::execl(FAIRSPLINE_CLI, "fairspline", "batch", "--report", "none", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(in[0]);
  ::close(out[1]);
  const std::string first = walk_request(5, 1).dump() + "\n# comment\n";
  ASSERT_EQ(::write(in[1], first.data(), first.size()), static_cast<ssize_t>(first.size()));
  std::string text;
  const bool streamed = read_lines(out[0], text, 1, 60);
  const std::string second = walk_request(6, 2).dump() + "\n";
  EXPECT_EQ(::write(in[1], second.data(), second.size()), static_cast<ssize_t>(second.size()));
  ::close(in[1]);
  read_lines(out[0], text, 2, 60);
  ::close(out[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(streamed) << "no record before the end of the input";
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const std::vector<json> records = parse_lines(text);
  ASSERT_EQ(records.size(), 2u) << text;
  EXPECT_EQ(records[0]["line"], 1);
  EXPECT_EQ(records[0]["segments"].size(), 4u);
  EXPECT_EQ(records[1]["line"], 3);
  EXPECT_EQ(records[1]["segments"].size(), 5u);
}

TEST_F(CliBatch, UsageAndIoErrorsExitTwo) {
  const fs::path in = file("in.jsonl", walk_request(5, 1).dump() + "\n");
  const CliRun negative = run("batch " + quote(in.string()) + " --threads -1");
  EXPECT_EQ(negative.exit_code, 2);
  EXPECT_NE(negative.err.find("--threads"), std::string::npos) << negative.err;
  EXPECT_EQ(negative.out, "");
  EXPECT_EQ(run("batch " + quote(in.string()) + " --threads many").exit_code, 2);
  const CliRun missing = run("batch " + quote((dir_ / "missing.jsonl").string()));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("fairspline: error [io_error]: cannot read '"), std::string::npos)
      << missing.err;
  EXPECT_NE(missing.err.find("missing.jsonl': No such file or directory"), std::string::npos)
      << missing.err;
  const CliRun directory = run("batch " + quote(dir_.string()));
  EXPECT_EQ(directory.exit_code, 2);
  EXPECT_NE(directory.err.find("it is a directory"), std::string::npos) << directory.err;
  const CliRun method = run("batch " + quote(in.string()) + " -m jaklic-zagar -m nope");
  EXPECT_EQ(method.exit_code, 2);
  EXPECT_NE(method.err.find("[unknown_method]"), std::string::npos) << method.err;
  EXPECT_EQ(method.out, "");
  EXPECT_EQ(run("batch " + quote(in.string()) + " --report most").exit_code, 2);
  const CliRun no_dir =
      run("batch " + quote(in.string()) + " -o " + quote((dir_ / "no/such/x.jsonl").string()));
  EXPECT_EQ(no_dir.exit_code, 2);
  EXPECT_NE(no_dir.err.find("cannot write"), std::string::npos) << no_dir.err;
  if (fs::exists("/dev/full")) {
    const CliRun full = run("batch " + quote(in.string()) + " -o /dev/full");
    EXPECT_EQ(full.exit_code, 2);
    EXPECT_NE(full.err.find("error while writing '/dev/full'"), std::string::npos) << full.err;
  }
  const CliRun help = run("batch --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--threads"), std::string::npos);
}

TEST_F(CliBatch, BestEffortAndAccuracyFromTheLineOrTheFlags) {
  // Kozak-Krajnc's G2 Newton stalls on this example (it has no G2 spline for the tangent rule's
  // end directions): the line fails unless a best effort is asked for, by the line
  // ("best_effort": true) or by --best-effort for every line.
  std::string csv = slurp(fs::path(FAIRSPLINE_SOURCE_DIR) / "examples" / "kozak-krajnc.csv");
  json points = json::array();
  std::istringstream lines(csv);
  for (std::string line; std::getline(lines, line);) {
    double x = 0, y = 0;
    if (std::sscanf(line.c_str(), "%lf,%lf", &x, &y) == 2) points.push_back({x, y});
  }
  json request = {{"points", points}, {"method", "kozak-krajnc"}, {"options", {{"g2", true}}}};
  json asked = request;
  asked["best_effort"] = true;
  const fs::path in = file("in.jsonl", request.dump() + "\n" + asked.dump() + "\n");
  const CliRun plain = run("batch " + quote(in.string()));
  EXPECT_EQ(plain.exit_code, 1);
  const std::vector<json> a = parse_lines(plain.out);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].at("error").at("code"), "infeasible");
  const json& solver = a[1].at("method_report").at("solver");
  EXPECT_EQ(solver.at("status"), "stalled");
  EXPECT_GT(solver.at("residual").get<double>(), solver.at("tolerance").get<double>());
  const CliRun flag = run("batch " + quote(in.string()) + " --best-effort");
  EXPECT_EQ(flag.exit_code, 0) << flag.err;
  const std::vector<json> b = parse_lines(flag.out);
  ASSERT_EQ(b.size(), 2u);
  b[0].at("method_report").at("solver");  // a curve, not an error
  // --accuracy overrides every line's; out of (0, 1) it fails each record with bad_option.
  const fs::path walk = file("walk.jsonl", walk_request(9, 3).dump() + "\n");
  const CliRun bad = run("batch " + quote(walk.string()) + " --accuracy 0");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(parse_lines(bad.out).at(0).at("error").at("code"), "bad_option");
  json coarse_request = walk_request(9, 3);
  coarse_request["accuracy"] = 0.0;
  const fs::path coarse = file("coarse.jsonl", coarse_request.dump() + "\n");
  EXPECT_EQ(run("batch " + quote(coarse.string())).exit_code, 1);
  EXPECT_EQ(run("batch " + quote(coarse.string()) + " --accuracy 1e-6").exit_code, 0);
}

TEST_F(CliBatch, NoDiagnosticsFromTheLineOrTheFlag) {
  // A Jaklič–Žagar record's per-point λ are diagnostics: left out by the line's
  // "diagnostics": false or by --no-diagnostics for every line; the summary stays.
  json request = walk_request(9, 3);
  request["method"] = "jaklic-zagar";
  json asked = request;
  asked["diagnostics"] = false;
  const fs::path in = file("in.jsonl", request.dump() + "\n" + asked.dump() + "\n");
  const CliRun lines = run("batch " + quote(in.string()));
  ASSERT_EQ(lines.exit_code, 0) << lines.err;
  const std::vector<json> a = parse_lines(lines.out);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].at("method_report").at("lambda").size(), 9u);
  EXPECT_FALSE(a[1].at("method_report").contains("lambda"));
  EXPECT_EQ(a[1].at("method_report").at("lambda_mode"), a[0].at("method_report").at("lambda_mode"));
  EXPECT_EQ(a[1].at("segments"), a[0].at("segments"));
  const CliRun flag = run("batch " + quote(in.string()) + " --no-diagnostics");
  ASSERT_EQ(flag.exit_code, 0) << flag.err;
  for (const json& r : parse_lines(flag.out)) {
    EXPECT_EQ(r.at("method_report"), a[1].at("method_report"));
  }
}

/// The text of member `key` of a compact one-line record ("\"key\":" up to its end).
std::string member_text(const std::string& record, const std::string& key) {
  const json parsed = json::parse(record);
  const std::string value = parsed.at(key).dump();
  const auto at = record.find("\"" + key + "\":");
  return at == std::string::npos ? "" : record.substr(at, key.size() + 3 + value.size());
}

std::vector<std::string> raw_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST_F(CliBatch, FieldsKeepOnlyTheNamedMembers) {
  json closed = walk_request(12, 8);
  closed["closed"] = true;
  closed["method"] = "li-strain";
  json repeated = walk_request(6, 9);
  repeated["points"][2] = repeated["points"][1];
  const std::string text =
      walk_request(20, 7).dump() + "\n" + repeated.dump() + "\nnot json\n" + closed.dump() + "\n";
  const fs::path in = file("in.jsonl", text);
  const CliRun whole = run("batch " + quote(in.string()) + " --report full");
  const CliRun cut = run("batch " + quote(in.string()) +
                         " --report full --fields 'segments, report.bending_energy,report.length'");
  EXPECT_EQ(cut.exit_code, 1);
  EXPECT_EQ(cut.err, whole.err);  // the same failures
  const std::vector<std::string> a = raw_lines(whole.out), b = raw_lines(cut.out);
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(b.size(), 4u);
  for (const std::size_t i : {0u, 3u}) {
    const json rec = json::parse(b[i]);
    std::vector<std::string> keys;
    for (auto it = rec.begin(); it != rec.end(); ++it) keys.push_back(it.key());
    // "line" and "method" always: they tell the records apart.
    EXPECT_EQ(keys, (std::vector<std::string>{"line", "method", "report", "segments"})) << b[i];
    EXPECT_EQ(rec["report"].size(), 2u);
    // The members kept are the whole record's, byte for byte.
    const json full = json::parse(a[i]);
    EXPECT_EQ(rec["report"]["bending_energy"], full["report"]["bending_energy"]);
    EXPECT_EQ(rec["report"]["length"], full["report"]["length"]);
    for (const std::string key : {"segments", "line", "method"}) {
      EXPECT_NE(member_text(a[i], key), "");
      EXPECT_EQ(member_text(b[i], key), member_text(a[i], key)) << key;
    }
    EXPECT_LT(b[i].size(), a[i].size() / 2);
  }
  // Error records are written whole.
  EXPECT_EQ(b[1], a[1]);
  EXPECT_EQ(b[2], a[2]);
  EXPECT_EQ(json::parse(b[1])["error"]["code"], "repeated_point");
  EXPECT_EQ(json::parse(b[2])["error"]["code"], "parse_error");

  // Members of the method's report, options and request may be named freely (they depend on
  // the method and the request); a name the object lacks leaves it out.
  const CliRun open = run("batch " + quote(in.string()) +
                          " --fields request.closed,method_report.nothing_like_this,options");
  const std::vector<json> c = parse_lines(open.out);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0]["request"], json::object());  // an open curve: "closed" is not written
  EXPECT_EQ(c[3]["request"], json({{"closed", true}}));
  EXPECT_EQ(c[3]["method_report"], json::object());
  EXPECT_EQ(c[3]["options"], json::parse(a[3])["options"]);
  EXPECT_EQ(c[3]["method"], "li-strain");
}

TEST_F(CliBatch, EveryFieldNamedGivesTheWholeRecordByteForByte) {
  // The member scan takes apart every record of the mixed lines (methods with their own
  // reports, open and closed, errors) and puts it together again unchanged.
  std::vector<std::optional<json>> requests;
  const fs::path in = file("mixed.jsonl", mixed_lines(120, requests));
  const CliRun whole = run("batch " + quote(in.string()) + " --report full");
  const CliRun named = run("batch " + quote(in.string()) +
                           " --report full --fields closed,knots,line,method,method_report,"
                           "options,points,report,request,segments,tangents");
  EXPECT_EQ(whole.exit_code, 1);
  EXPECT_EQ(named.exit_code, 1);
  ASSERT_GT(whole.out.size(), 50'000u);
  EXPECT_TRUE(named.out == whole.out);
  // The same at the basic level, on one thread, with the names in another order.
  const CliRun basic = run("batch " + quote(in.string()) + " --threads 1");
  const CliRun basic_named =
      run("batch " + quote(in.string()) +
          " --threads 1 --fields tangents,segments,request,report,points,options,"
          "method_report,knots,closed");
  EXPECT_TRUE(basic_named.out == basic.out);
}

TEST_F(CliBatch, UnknownFieldsAreUsageErrors) {
  const fs::path in = file("in.jsonl", walk_request(5, 1).dump() + "\n");
  for (const std::string bad :
       {"segmnts", "segments.bezier", "report.nope", "report.", "segments,,points",
        "method_report.", "request.points.x", "error", "", "segments,"}) {
    const CliRun r = run("batch " + quote(in.string()) + " --fields " + quote(bad));
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_EQ(r.out, "") << bad;
    EXPECT_NE(r.err.find("fairspline: error [invalid_argument]: --fields: unknown field '"),
              std::string::npos)
        << bad << ": " << r.err;
    // The message lists what there is.
    EXPECT_NE(r.err.find("the fields are closed, knots, line, method, method_report, options, "
                         "points, report, request, segments, tangents; report.NAME for NAME "
                         "one of bending_energy, "),
              std::string::npos)
        << r.err;
  }
  const CliRun none =
      run("batch " + quote(in.string()) + " --report none --fields segments,report.length");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("--report none writes none"), std::string::npos) << none.err;
  EXPECT_EQ(run("batch " + quote(in.string()) + " --report none --fields segments").exit_code, 0);
}

}  // namespace

#endif  // FAIRSPLINE_CLI
