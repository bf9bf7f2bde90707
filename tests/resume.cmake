# Interruption tests of `cmc run` (tests/resume_test.py, which says what each
# checks): runs stopped by SIGKILL at named test points (CMC_TEST_KILL_AT, not timers) and
# resumed must equal uninterrupted runs bit for bit; one defect per test, named after it.
# Each works in its own folder under build/resume-tests/.
foreach(test kill_anywhere observables_only inside_step older_checkpoint stopping_limit stopped_run D1_pulloff D2_jump_scale D3_counters D8_stale_summary)
  add_test(NAME resume.${test}
           COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/resume_test.py $<TARGET_FILE:cmc>
                   ${CMAKE_BINARY_DIR}/resume-tests ${test})
  set_tests_properties(resume.${test} PROPERTIES LABELS "quick;python" TIMEOUT 300)
endforeach()
# One owner per output folder (D7): a second run, validate or refine on a folder in use.
add_test(NAME lock.D7_one_owner
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/resume_test.py $<TARGET_FILE:cmc>
                 ${CMAKE_BINARY_DIR}/resume-tests D7_lock)
set_tests_properties(lock.D7_one_owner PROPERTIES LABELS "quick;python" TIMEOUT 300)
# A malformed test-point variable is bad input (exit 2), before anything is written.
add_test(NAME cli.bad_test_point
         COMMAND sh -c "rm -rf ${CMAKE_BINARY_DIR}/bad-test-point; CMC_TEST_KILL_AT=step:0 $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml --set grid.n=64 --out ${CMAKE_BINARY_DIR}/bad-test-point 2>&1 | grep -q 'CMC_TEST_KILL_AT: expected NAME:N' && test ! -e ${CMAKE_BINARY_DIR}/bad-test-point")
set_tests_properties(cli.bad_test_point PROPERTIES LABELS "quick;python")
# A start from a coarser run of the same case (cmc run --start-from; tests/start_from_test.py
# says what each checks): the state it ends in, resuming it, and the inputs it refuses.
foreach(test same_state resume bad_input)
  add_test(NAME start_from.${test}
           COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/start_from_test.py $<TARGET_FILE:cmc>
                   ${CMAKE_BINARY_DIR}/start-from-tests ${test})
  set_tests_properties(start_from.${test} PROPERTIES LABELS "quick;python" TIMEOUT 300)
endforeach()
# A run capped by solver.max_seconds ends within 10 % of its cap with its summary written,
# not_converged (tests/time_limit_test.py).
add_test(NAME time_limit.capped_run
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/time_limit_test.py $<TARGET_FILE:cmc>
                 ${CMAKE_BINARY_DIR}/time-limit-tests)
set_tests_properties(time_limit.capped_run PROPERTIES LABELS "quick;python" TIMEOUT 120)
