// placeholder: replaced by the reference-curve work (issue 5)
#include "commands.hpp"
#include <cstdio>
namespace cmc::app {
int cmd_reference(int, char**) { std::fputs("cmc reference: not available yet\n", stderr); return kUsage; }
}  // namespace cmc::app
