#include "commands.hpp"

#include "cmc/contact/quasi_static/Memory.hpp"
#include "cmc/grid/Backend.hpp"
#include "cmc/grid/Ranks.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>

namespace cmc::app {

std::string Args::option(const std::string& name, const std::string& def) const {
  for (const auto& [k, v] : options)
    if (k == name) return v;
  return def;
}

namespace {
constexpr long kMaxThreads = 65536;
// Seconds between progress lines when stderr is a file or a pipe: CMC_PROGRESS_EVERY
// (a number >= 0; 0 prints every line the solver reports), else 30.
double progress_every() {
  const char* v = std::getenv("CMC_PROGRESS_EVERY");
  if (!v || !*v) return 30.0;
  char* end = nullptr;
  const double s = std::strtod(v, &end);
  if (end == v || *end != '\0' || !std::isfinite(s) || s < 0.0)
    throw CaseError(std::string("environment variable CMC_PROGRESS_EVERY = '") + v +
                    "': expected the seconds between progress lines in a log, a number >= 0 (unset: 30)");
  return s;
}
}  // namespace

// CMC_THREADS: a positive whole number of threads (unset or empty: the machine's).
void check_threads_variable() {
  const char* v = std::getenv("CMC_THREADS");
  if (!v || !*v) return;
  char* end = nullptr;
  errno = 0;
  const long n = std::strtol(v, &end, 10);
  if (end == v || *end != '\0' || errno == ERANGE || n < 1 || n > kMaxThreads)
    throw CaseError(std::string("environment variable CMC_THREADS = '") + v + "': expected a whole number of threads from 1 to " +
                    std::to_string(kMaxThreads) + " (unset: all of this machine's)");
}

Args parse_args(int argc, char** argv, int first, const std::vector<std::string>& valued,
                const std::vector<std::string>& repeatable) {
  progress_every();  // a malformed value is refused before anything is read or written
  check_threads_variable();
  Args a;
  bool out_given = false;
  a.quiet = !is_root();  // in a distributed run rank 0 alone prints
  for (int i = first; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&](const std::string& name) {
      if (i + 1 >= argc) throw CaseError(name + " needs a value");
      // An option is not a value: `--out --quiet` would make a folder named --quiet.
      if (std::string(argv[i + 1]).rfind("--", 0) == 0)
        throw CaseError(name + " needs a value, got the option " + argv[i + 1] + " (write " + name + "=" + argv[i + 1] +
                        " if that is meant)");
      return std::string(argv[++i]);
    };
    const auto eq = s.find('=');
    const std::string name = s.substr(0, eq);
    // A single-value option given twice is refused: which one was meant is not for cmc to guess.
    auto once = [&](bool given) {
      if (given) throw CaseError(name + " is given twice: give it once");
    };
    auto take = [&]() { return eq == std::string::npos ? value(name) : s.substr(eq + 1); };
    auto in = [&](const std::vector<std::string>& names) {
      return std::find(names.begin(), names.end(), name) != names.end();
    };
    const bool seen = std::any_of(a.options.begin(), a.options.end(), [&](const auto& o) { return o.first == name; });
    if (s == "-h" || s == "--help") {
      a.help = true;
    } else if (s == "--quiet" || s == "-q") {
      a.quiet = true;
    } else if (s == "--resume") {
      a.resume = true;
    } else if (name == "--out" || name == "-o") {
      once(out_given);
      out_given = true;
      a.out = take();
    } else if (name == "--set") {
      a.overrides.push_back(take());
    } else if (in(valued)) {
      once(seen && !in(repeatable));
      a.options.emplace_back(name, take());
    } else if (s.size() > 1 && s[0] == '-') {
      throw CaseError("unknown option " + s + " (see --help)");
    } else {
      a.positional.push_back(s);
    }
  }
  return a;
}

std::string override_key(const std::string& assignment) {
  std::string key = assignment.substr(0, assignment.find('='));
  key.erase(0, std::min(key.find_first_not_of(" \t"), key.size()));
  key.erase(key.find_last_not_of(" \t") + 1);
  return key;
}

bool is_grid_key(const std::string& key) { return key == "grid.n" || key == "grid.nx" || key == "grid.ny"; }

std::vector<int> take_grids(int argc, char** argv, std::vector<char*>& rest) {
  std::vector<int> grids;
  for (int i = 0; i < argc; ++i) {
    if (std::string(argv[i]) != "--grids") {
      rest.push_back(argv[i]);
      continue;
    }
    const std::size_t before = grids.size();
    while (i + 1 < argc) {
      char* end = nullptr;
      errno = 0;
      const long long n = std::strtoll(argv[i + 1], &end, 10);
      if (end == argv[i + 1] || *end != '\0') {
        // What follows the sizes is an option or the case file: anything else is a bad size.
        const std::string next = argv[i + 1];
        if (next[0] != '-' && !std::filesystem::exists(next))
          throw CaseError("--grids: '" + next + "' is neither a whole number (a grid size) nor an existing case file");
        break;
      }
      // Bounded before it is narrowed to int (CaseLimits, as grid.n in a case file).
      if (errno == ERANGE || n < 2 || n > CaseLimits::kMaxGridSide || (!grids.empty() && n <= grids.back()))
        throw CaseError(std::string("--grids: expected increasing grid sizes from 2 to ") +
                        std::to_string(CaseLimits::kMaxGridSide) + ", got " + argv[i + 1]);
      grids.push_back(int(n)), ++i;
    }
    if (grids.size() == before) throw CaseError("--grids needs grid sizes, e.g. --grids 64 128");
  }
  return grids;
}

void refuse_grid_overrides(const std::vector<std::string>& overrides, const std::vector<int>& grids,
                           const std::string& command) {
  if (grids.empty()) return;
  std::string list;
  for (int n : grids) list.append(" ").append(std::to_string(n));
  for (const auto& o : overrides) {
    const std::string key = override_key(o);
    if (is_grid_key(key))
      throw CaseError("--set " + o + " overrides --grids" + list + ": " + command + " sets " + key +
                      " for each grid itself; drop the --set, or give the grids with --grids");
  }
}

void require_backend(const Case& c) {
  std::string why;
  if (c.grid.backend == "cuda" && !cuda::available(&why)) throw std::runtime_error(c.file + ": " + why);
}

void print_memory_plan(const Case& c, bool quiet) {
  if (quiet) return;
  const MemoryEstimate e = estimate_memory(c);
  std::optional<double> avail = available_memory();
  if (avail) *avail /= double(memory_split().ranks_here);
  const std::string on = ranks() > 1 ? " on " + std::to_string(ranks()) + " MPI ranks" : "";
  std::fprintf(stderr, "%s: %d x %d points%s, about %s of memory at the peak (%s)%s%s%s\n", c.name.c_str(), c.grid.nx,
               c.grid.ny, on.c_str(), memory_text(e.bytes).c_str(), e.what.c_str(), avail ? "; available: " : "",
               avail ? memory_text(*avail).c_str() : "", avail && ranks() > 1 ? " per rank" : "");
  if (c.grid.backend == "cuda") {
    const bool pre = c.solver.precondition;
    std::string why;
    const std::string dev = cuda::available(&why) ? cuda::device_description() : "none: " + why;
    const bool qs = c.solver.kind == SolverKind::QuasiStatic;
    const std::size_t work = cuda::fft_work_bytes(c.grid.nx, c.grid.ny);
    const std::size_t bytes = qs ? qs::device_bytes(c.grid.nx, c.grid.ny, pre, work)
                                 : pk::device_bytes(c.grid.nx, c.grid.ny, pre, work);
    std::fprintf(stderr, "%s: %s fields on the GPU: about %s of device memory (GPU: %s)\n", c.name.c_str(),
                 qs ? "the quasi-static solver's" : "Polonsky-Keer's", memory_text(double(bytes)).c_str(), dev.c_str());
  }
}

Progress make_progress(bool quiet, int* step, std::chrono::steady_clock::time_point t0, int total_steps,
                       int first_step) {
  if (quiet) return {};
  // On a terminal one line, rewritten in place; into a file or a pipe (a batch job's log) a
  // line of its own at most every `every` seconds, so that a long run shows it is alive.
  const double every = progress_every();
  const bool tty = isatty(STDERR_FILENO);
  auto last = std::make_shared<double>(0.0);
  return [step, t0, total_steps, first_step, tty, every, last](const ProgressPoint& p) {
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!tty) {
      if (el - *last < every) return;
      *last = el;
    }
    std::fprintf(stderr, "%s  step %d%s%s  iteration %5d", tty ? "\r" : "", *step, total_steps ? "/" : "",
                 total_steps ? std::to_string(total_steps).c_str() : "", p.iteration);
    if (p.inner) std::fprintf(stderr, "  outer step %4d  Polonsky-Keer residual %.3e", p.outer, p.residual);
    else if (p.outer > 0) std::fprintf(stderr, "  outer step %4d  tension change %.3e", p.outer, p.residual);
    else std::fprintf(stderr, "  residual %.3e", p.residual);
    std::fprintf(stderr, "  elapsed %7.1f s", el);
    const int solved = *step - first_step;  // steps finished by this process, in el
    if (total_steps && solved > 0) std::fprintf(stderr, "  left ~%7.0f s", el / solved * (total_steps - *step));
    std::fputs(tty ? "  " : "\n", stderr);
    std::fflush(stderr);
  };
}

}  // namespace cmc::app
