// Test points: named places in a run where a test can stop the process, so that the
// interruption tests (tests/resume_test.py) interrupt a run at a chosen place instead of
// racing it with a timer (which is unreliable on a loaded machine). Off unless the
// environment asks for one:
//   CMC_TEST_KILL_AT=NAME:N    the process raises SIGKILL on itself the N-th time (from 1)
//                              it reaches the point NAME;
//   CMC_TEST_PAUSE_AT=NAME:N   it stops there (printing "cmc: test point NAME:N: paused,
//                              pid P" on stderr) until the file named by CMC_TEST_CONTINUE
//                              exists, then goes on;
//   CMC_TEST_TRACE=1           it prints "cmc: test point NAME:N" on stderr at every point
//                              (to choose where to stop it).
// The points (run/Driver.cpp):
//   solve   before every solve (a load step's solves, sub-steps, pull-off refinement);
//   step    after a load step's checkpoint (between two steps);
//   refine  after the checkpoint of a pull-off refinement solve;
//   outer   between two outer steps of a quasi-static solve (after the checkpoint inside
//           the step, where one is due: cmc run --checkpoint-every).
#pragma once

namespace cmc {

// Checks the variables above (CaseError naming the variable when one is malformed).
void check_test_points();
// Marks that the run has reached the point `name` (see above).
void test_point(const char* name);

}  // namespace cmc
