#include "cmc/run/TestPoints.hpp"

#include "cmc/input/Case.hpp"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <thread>

namespace cmc {

namespace {

struct Point {
  std::string name;
  long count = 0;  // 0: none
};

const char* const kNames[] = {"solve", "step", "refine", "outer"};

Point parse(const char* variable) {
  const char* v = std::getenv(variable);
  if (!v || !*v) return {};
  const std::string s = v;
  const auto colon = s.find(':');
  Point p;
  bool ok = colon != std::string::npos;
  if (ok) {
    p.name = s.substr(0, colon);
    char* end = nullptr;
    p.count = std::strtol(s.c_str() + colon + 1, &end, 10);
    ok = end != s.c_str() + colon + 1 && *end == '\0' && p.count >= 1;
    bool known = false;
    for (const char* n : kNames) known |= p.name == n;
    ok = ok && known;
  }
  if (!ok)
    throw CaseError(std::string(variable) + ": expected NAME:N with NAME one of solve, step, refine, outer and N >= 1, got '" +
                    s + "'");
  return p;
}

struct Points {
  Point kill = parse("CMC_TEST_KILL_AT"), pause = parse("CMC_TEST_PAUSE_AT");
  bool trace = std::getenv("CMC_TEST_TRACE") && std::string(std::getenv("CMC_TEST_TRACE")) == "1";
  std::string resume_file = std::getenv("CMC_TEST_CONTINUE") ? std::getenv("CMC_TEST_CONTINUE") : "";
  std::map<std::string, long> reached;
  Points() {
    if (pause.count && resume_file.empty())
      throw CaseError("CMC_TEST_PAUSE_AT needs CMC_TEST_CONTINUE: the file whose creation ends the pause");
  }
};

Points& points() {
  static Points p;
  return p;
}

}  // namespace

void check_test_points() { points(); }

void test_point(const char* name) {
  Points& p = points();
  if (!p.kill.count && !p.pause.count && !p.trace) return;
  const long n = ++p.reached[name];
  if (p.trace) std::fprintf(stderr, "cmc: test point %s:%ld\n", name, n);
  if (p.pause.count == n && p.pause.name == name) {
    std::fprintf(stderr, "cmc: test point %s:%ld: paused, pid %d\n", name, n, int(::getpid()));
    std::fflush(stderr);
    while (!std::filesystem::exists(p.resume_file)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (p.kill.count == n && p.kill.name == name) {
    std::fflush(nullptr);
    ::raise(SIGKILL);
  }
}

}  // namespace cmc
