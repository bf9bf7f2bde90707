# libFuzzer targets (CMC_FUZZ=ON; clang): one executable per reader, fuzz_<name>, from
# tests/fuzz/fuzz_<name>.cpp, with its seed corpus in tests/fuzz/corpus/<name>/.
# scripts/fuzz.sh builds and runs them; docs/developer/testing.md says how.
set(CMC_FUZZ_TARGETS case ascii_heights hdf5_heights hdf5_bytes check_csv)
foreach(name ${CMC_FUZZ_TARGETS})
  add_executable(fuzz_${name} ${CMAKE_SOURCE_DIR}/tests/fuzz/fuzz_${name}.cpp)
  target_compile_options(fuzz_${name} PRIVATE -fsanitize=fuzzer -Wall -Wextra)
  target_link_options(fuzz_${name} PRIVATE -fsanitize=fuzzer)
  target_link_libraries(fuzz_${name} PRIVATE cmclib)
endforeach()
add_custom_target(cmc_fuzz)
foreach(name ${CMC_FUZZ_TARGETS})
  add_dependencies(cmc_fuzz fuzz_${name})
endforeach()
