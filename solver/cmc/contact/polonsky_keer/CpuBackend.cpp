// Polonsky-Keer on the CPU: the iteration (Iteration.hpp) over the CPU backend
// (CpuBackend.hpp), in place on the state's fields.
#include "cmc/contact/polonsky_keer/CpuBackend.hpp"

namespace cmc {

pk::End pk::solve_on_cpu(std::unique_ptr<PolonskyKeer::Work>& work, HalfSpace& hs, const Field& h,
                         const PolonskyKeer::Options& o, double h_scale, const Target& target, ContactState& st,
                         const Start& start, SolveResult& res) {
  if (!work) work = std::make_unique<PolonskyKeer::Work>();
  End end;
  {  // the backend counts its transforms when it goes, before its work arrays do
    Host host(hs, h, st, *work, start.warm, start.precondition, o.fused_sweeps);
    end = iterate(host, o, h_scale, target, start, res);
  }
  if (!o.keep_work) work.reset();
  return end;
}

}  // namespace cmc
