# ctest's side of tests/compile_fail: compiles backend_missing_a_pass.cpp for one solver
# (-DSOLVER=CMC_POLONSKY_KEER or CMC_QUASI_STATIC) twice, syntax only:
#   with every pass (CMC_EVERY_PASS): it must compile (the file is sound);
#   without one:                       it must fail, naming the concept CONCEPT and the
#                                      pass PASS in the compiler's output.
# Arguments: CXX (the compiler), SOURCE, INCLUDE (solver/), SOLVER, CONCEPT, PASS.
set(compile ${CXX} -std=c++20 -fsyntax-only -I${INCLUDE} -D${SOLVER} ${SOURCE})
execute_process(COMMAND ${compile} -DCMC_EVERY_PASS RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the backend with every pass does not compile (${SOLVER}):\n${out}")
endif()
execute_process(COMMAND ${compile} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc EQUAL 0)
  message(FATAL_ERROR "a backend without ${PASS} compiled (${SOLVER}): the iteration does not require ${CONCEPT}")
endif()
string(FIND "${out}" "${CONCEPT}" at_concept)
string(FIND "${out}" "${PASS}" at_pass)
if(at_concept EQUAL -1 OR at_pass EQUAL -1)
  message(FATAL_ERROR "a backend without ${PASS} failed to compile, but the message names not both ${CONCEPT} and "
                      "${PASS} (${SOLVER}):\n${out}")
endif()
message(STATUS "a backend without ${PASS} fails to compile, naming ${CONCEPT}")
