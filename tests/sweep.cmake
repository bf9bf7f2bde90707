# cmc sweep (tests/sweep_test.py says what each checks): its points equal `cmc run` with the
# same --set bit for bit, an interrupted sweep resumes, finished points are skipped, and bad
# input is refused before anything runs; scripts/scaled_family.py's runs go through it.
# Each works in its own folder under build/sweep-tests/.
foreach(test same_as_run resume skip refusals scaled_family many_values folders)
  add_test(NAME sweep.${test}
           COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/sweep_test.py $<TARGET_FILE:cmc>
                   ${CMAKE_BINARY_DIR}/sweep-tests ${test})
  set_tests_properties(sweep.${test} PROPERTIES LABELS "quick;python" TIMEOUT 300)
endforeach()
