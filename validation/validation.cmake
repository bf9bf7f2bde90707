# Every case with a [validation] section becomes one ctest test, labelled
# 'validation' (plus 'slow' when its file name says so: cases/validation/*.slow.toml).
# Each runs `cmc validate` on the case; results land in build/validation/<case>/.
file(GLOB CMC_VALIDATION_CASES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/cases/validation/*.toml)
foreach(case_file ${CMC_VALIDATION_CASES})
  get_filename_component(case_name ${case_file} NAME_WE)
  set(labels validation)
  if(case_file MATCHES "\\.slow\\.toml$")
    set(labels validation slow)
  endif()
  add_test(NAME validate.${case_name}
           COMMAND cmc validate ${case_file} --quiet --out ${CMAKE_BINARY_DIR}/validation)
  set_tests_properties(validate.${case_name} PROPERTIES LABELS "${labels}" TIMEOUT 1800)
endforeach()

# The harness can fail: the same Hertz case on a grid too coarse for its tolerance
# (measured: penetration error 1.3e-3 > 1e-3 at n = 32) must exit with code 5.
add_test(NAME validate.can_fail
         COMMAND sh -c "$<TARGET_FILE:cmc> validate ${CMAKE_SOURCE_DIR}/cases/validation/hertz-free.toml --quiet --set grid.n=32; test $? -eq 5")
set_tests_properties(validate.can_fail PROPERTIES LABELS validation)

# The report scripts on synthetic inputs (Debian's python3 with matplotlib/h5py).
add_test(NAME reports.selftest COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/reports/selftest.py)
set_tests_properties(reports.selftest PROPERTIES LABELS quick)

# cmc surface prints the challenge surface's statistics (a 256² low-passed preview).
add_test(NAME cli.surface COMMAND cmc surface ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load.toml --set grid.n=256)
set_tests_properties(cli.surface PROPERTIES LABELS quick PASS_REGULAR_EXPRESSION "R_c +[0-9.e+-]+ m")

# cmc refine: a three-grid study of the hard-wall challenge case on 64², 128², 256²
# (about a second). It must write the table with an observed order in the penetration
# row, and a second call must reuse all three finished grids instead of rerunning them.
set(CMC_REFINE_OUT ${CMAKE_BINARY_DIR}/cli-refine)
set(CMC_REFINE_CMD "$<TARGET_FILE:cmc> refine ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml --grids 64 128 256 --out ${CMC_REFINE_OUT}")
add_test(NAME cli.refine
         COMMAND sh -c "rm -rf ${CMC_REFINE_OUT} && ${CMC_REFINE_CMD} --quiet >/dev/null && grep -Eq '^[|] penetration [|].*[|] [0-9]+[.][0-9]+ [|]$' ${CMC_REFINE_OUT}/refinement.md && test \"$(${CMC_REFINE_CMD} 2>&1 >/dev/null | grep -c 'finished earlier')\" -eq 3")
set_tests_properties(cli.refine PROPERTIES LABELS quick)
# Grids out of order are bad input (exit code 2), and nothing is run.
add_test(NAME cli.refine_bad_grids
         COMMAND sh -c "$<TARGET_FILE:cmc> refine ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml --grids 256 128 --out ${CMAKE_BINARY_DIR}/cli-refine-bad; test $? -eq 2 && test ! -e ${CMAKE_BINARY_DIR}/cli-refine-bad")
set_tests_properties(cli.refine_bad_grids PROPERTIES LABELS quick)
