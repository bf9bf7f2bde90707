# A solver's backend that lacks a pass does not compile, and the compiler names the backend
# concept its iteration requires (contact/polonsky_keer/Contract.hpp,
# contact/quasi_static/Contract.hpp): expect_no_compile.cmake, label quick.
foreach(solver "CMC_POLONSKY_KEER;PolonskyKeerBackend;stiffness_and_sums;polonsky_keer"
               "CMC_QUASI_STATIC;QuasiStaticBackend;predict;quasi_static")
  list(GET solver 0 macro)
  list(GET solver 1 concept)
  list(GET solver 2 pass)
  list(GET solver 3 name)
  add_test(NAME compile_fail.${name}_backend_without_${pass}
           COMMAND ${CMAKE_COMMAND} -DCXX=${CMAKE_CXX_COMPILER} -DINCLUDE=${CMAKE_SOURCE_DIR}/solver
                   -DSOURCE=${CMAKE_SOURCE_DIR}/tests/compile_fail/backend_missing_a_pass.cpp -DSOLVER=${macro}
                   -DCONCEPT=${concept} -DPASS=${pass} -P ${CMAKE_SOURCE_DIR}/tests/compile_fail/expect_no_compile.cmake)
  set_tests_properties(compile_fail.${name}_backend_without_${pass} PROPERTIES LABELS quick)
endforeach()
