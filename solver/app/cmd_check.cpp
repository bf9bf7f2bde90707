// placeholder: replaced by the prediction checker (issue 5)
#include "commands.hpp"
#include <cstdio>
namespace cmc::app {
int cmd_check(int, char**) { std::fputs("cmc check: not available yet\n", stderr); return kUsage; }
}  // namespace cmc::app
