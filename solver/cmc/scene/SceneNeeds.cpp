// What a scene needs and what a run leaves out (SceneNeeds.hpp).
#include "cmc/scene/SceneNeeds.hpp"

namespace cmc {

SceneNeeds scene_needs(const Case& c) {
  SceneNeeds n;
  n.interaction = std::string(kind_name(c.interaction.kind));
  n.adhesion = c.interaction.kind != InteractionKind::HardWall;
  n.solver = std::string(kind_name(c.solver.kind));
  n.observables = c.observables.enabled;
  n.fields_written = c.write_fields;
  n.boundary = c.grid.periodic ? "periodic" : "free";
  n.solver_fields = solver_fields(c);
  if (!n.adhesion)
    n.left_out.push_back("adhesion: no interaction law and no adhesive field (tension, cascade, energy terms); "
                         "Polonsky-Keer on the hard wall");
  if (!n.observables)
    n.left_out.push_back("observables: no distributions, patches, spectrum or cross-section ([observables] "
                         "enabled = false); the step's scalars only");
  if (!n.fields_written) n.left_out.push_back("fields: no result.h5 ([output] fields = false)");
  if (c.grid.periodic) n.left_out.push_back("zero padding: a periodic cell transforms on its own nx x ny grid");
  else n.left_out.push_back("periodic images: a free patch transforms on a zero-padded 2nx x 2ny grid");
  return n;
}

}  // namespace cmc
