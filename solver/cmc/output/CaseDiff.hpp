// Whether a checkpoint was written by the case being run: the resolved case a checkpoint
// keeps (to_json text) against the one a resumed run resolves now.
//
// A long run outlives versions of cmc: a key added after the checkpoint was written (e.g.
// grid.backend) appears in the running version's resolved case and not in the checkpoint's. Such a key
// is accepted when it holds its documented default (case_defaults(), Case.hpp), which is
// by construction what the older version ran; any other difference refuses the resume,
// and the first difference is named so that the user can see which --set went astray.
// case.description is free text that no solver reads: a changed description is reported,
// not refused.
// A stopping limit (solver.max_outer_steps) may change: the path of a solve does not depend
// on its limit until the limit is reached, so the resumed run is the run a fresh one with
// the new limit makes, provided the checkpoint has not yet passed it. compare_cases cannot
// see how far the checkpoint got: it lists the change, and the caller (Checkpoint.cpp) refuses
// a limit that the checkpoint's outer steps have already reached. The way to end a run
// that creeps towards its tolerance for hours: resume it with a limit just above where it
// stands, and it stops there with status not_converged and its last tension change.
#pragma once

#include <string>
#include <vector>

namespace cmc {

struct CaseDiff {
  std::string mismatch;                // empty: the same case; else "key a.b: ... " (first difference)
  std::vector<std::string> defaulted;  // "a.b = v": keys absent from the checkpoint, at their default here
  std::vector<std::string> text_changed;  // free-text keys that differ (the run goes on with the new text)
  std::vector<std::string> limits_changed;  // "a.b: v in the checkpoint, v' here": stopping limits
  bool same() const { return mismatch.empty(); }
};

CaseDiff compare_cases(const std::string& checkpoint_json, const std::string& current_json);

}  // namespace cmc
