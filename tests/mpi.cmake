# Distributed runs against serial ones (tests/mpi_test.py says what each
# checks), registered in the MPI build (-DCMC_MPI=ON, build-mpi/) with the label 'mpi'.
# They need the serial build's program too: CMC_SERIAL_CMC (default build/cmc).
set(CMC_SERIAL_CMC "${CMAKE_SOURCE_DIR}/build/cmc" CACHE FILEPATH "the serial build's cmc, for the mpi tests")
foreach(test hertz_periodic hertz_free westergaard_2d challenge_hardwall adhesive_sphere adhesive_sphere_free
             quasi_static_free challenge_adhesive
             challenge_quasi_static memory rerun_bits
             one_rank resume refusals)
  add_test(NAME mpi.${test}
           COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/mpi_test.py ${CMC_SERIAL_CMC} $<TARGET_FILE:cmc>
                   ${CMAKE_BINARY_DIR}/mpi-tests ${test})
  # Two ranks each: one test at a time on the 2-core CI machine (RUN_SERIAL).
  set_tests_properties(mpi.${test} PROPERTIES LABELS "mpi;python" TIMEOUT 600 RUN_SERIAL TRUE)
endforeach()
