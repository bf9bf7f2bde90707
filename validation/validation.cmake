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
