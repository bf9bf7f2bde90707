# Input sizes and file readers, through the cmc program: bad input exits with
# code 2 before anything is solved, and nothing is written. The parser's side of each is
# in tests/test_inputs.cpp (Inputs.*). cmc_cli_test: validation/validation.cmake.
set(CMC_INPUTS ${CMAKE_BINARY_DIR}/cli-inputs)
set(CMC_HERTZ ${CMAKE_SOURCE_DIR}/cases/validation/hertz-free.toml)
# D9: a case name with ../ wrote `cmc validate` results outside --out.
cmc_cli_test(input.D9_validate_name_escape "rm -rf ${CMC_INPUTS}/d9 && mkdir -p ${CMC_INPUTS}/d9/out && $<TARGET_FILE:cmc> validate ${CMC_HERTZ} --quiet --set grid.n=32 --set case.name=../escaped --out ${CMC_INPUTS}/d9/out; test $? -eq 2 && test ! -e ${CMC_INPUTS}/d9/escaped && test -z \"$(ls -A ${CMC_INPUTS}/d9/out)\"")
# D10: a 300-byte case name failed only after the solve, when its folder was made.
string(REPEAT x 300 CMC_LONG_NAME)
cmc_cli_test(input.D10_long_name_before_solve "rm -rf ${CMC_INPUTS}/d10 && $<TARGET_FILE:cmc> validate ${CMC_HERTZ} --quiet --set grid.n=32 --set case.name=${CMC_LONG_NAME} --out ${CMC_INPUTS}/d10 2>${CMC_INPUTS}-d10.err; test $? -eq 2 && grep -q 'at most 100 bytes' ${CMC_INPUTS}-d10.err && test ! -e ${CMC_INPUTS}/d10")
# D11: a folder or a pipe as the case file read as an empty case ("missing [case]").
cmc_cli_test(input.D11_case_is_folder "rm -rf ${CMC_INPUTS}/d11; $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases --out ${CMC_INPUTS}/d11 2>${CMC_INPUTS}-d11.err; test $? -eq 2 && grep -q 'cases: is a folder, expected a case file (TOML)' ${CMC_INPUTS}-d11.err && test ! -e ${CMC_INPUTS}/d11")
cmc_cli_test(input.D11_case_from_pipe "rm -rf ${CMC_INPUTS}/d11p; cat ${CMC_HERTZ} | $<TARGET_FILE:cmc> run /dev/stdin --out ${CMC_INPUTS}/d11p 2>${CMC_INPUTS}-d11p.err; test $? -eq 2 && grep -q '/dev/stdin: is not a regular file (a pipe, terminal or device)' ${CMC_INPUTS}-d11p.err && test ! -e ${CMC_INPUTS}/d11p")
# A load-controlled adhesive step whose first inner solve stops before its tolerance handed
# on an empty state: the observables then failed with an internal error (exit 4, "field
# size does not match grid"). It is a step that did not converge: exit 3, a summary that
# says so, and its observables from where the solve stopped.
cmc_cli_test(input.unconverged_first_adhesive_step "rm -rf ${CMC_INPUTS}/unconv; $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load.toml --quiet --set grid.n=64 --set solver.kind=\\\"adhesive_cg\\\" --set solver.max_iterations=5 --set loading.max_halvings=0 --set output.fields=false --out ${CMC_INPUTS}/unconv 2>${CMC_INPUTS}-unconv.err; test $? -eq 3 && grep -q '\"status\" : \"not_converged\"' ${CMC_INPUTS}/unconv/summary.json && grep -q 'contact_fraction' ${CMC_INPUTS}/unconv/summary.json")
# Shared bases (base = "other.toml", input/CaseFile.cpp; the parser's side is in
# tests/test_case_bases.cpp): a missing base and a cycle exit 2 naming the including file,
# its base key and the base, and nothing is written; a challenge case resolves to the whole
# case (its base's surface and load in summary.json, which names no base).
set(CMC_BASES ${CMAKE_SOURCE_DIR}/tests/data/bases)
cmc_cli_test(input.base_missing "rm -rf ${CMC_INPUTS}/base-missing; $<TARGET_FILE:cmc> run ${CMC_BASES}/missing.toml --out ${CMC_INPUTS}/base-missing 2>${CMC_INPUTS}-base-missing.err; test $? -eq 2 && grep -q 'missing.toml: base = \"no-such-base.toml\": .*bases/no-such-base.toml: cannot open the case file: no such file' ${CMC_INPUTS}-base-missing.err && test ! -e ${CMC_INPUTS}/base-missing")
cmc_cli_test(input.base_cycle "rm -rf ${CMC_INPUTS}/base-cycle; $<TARGET_FILE:cmc> run ${CMC_BASES}/cycle-a.toml --out ${CMC_INPUTS}/base-cycle 2>${CMC_INPUTS}-base-cycle.err; test $? -eq 2 && grep -q 'cycle-b.toml: base = \"cycle-a.toml\": a cycle of bases (cycle-a.toml -> cycle-b.toml -> cycle-a.toml)' ${CMC_INPUTS}-base-cycle.err && test ! -e ${CMC_INPUTS}/base-cycle")
cmc_cli_test(input.base_challenge_resolved "rm -rf ${CMC_INPUTS}/base-challenge; $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml --quiet --set grid.n=32 --out ${CMC_INPUTS}/base-challenge && grep -q '\"seed\" : 28' ${CMC_INPUTS}/base-challenge/summary.json && grep -q '\"contact_modulus\" : 25000000' ${CMC_INPUTS}/base-challenge/summary.json && grep -q '\"kind\" : \"hard_wall\"' ${CMC_INPUTS}/base-challenge/summary.json && ! grep -q '\"base\"' ${CMC_INPUTS}/base-challenge/summary.json")
# Outputs that respect what they replace, a checker that log axes cannot fool, and input
# errors refused before any solve: tests/reliability.cmake.
include(${CMAKE_CURRENT_LIST_DIR}/reliability.cmake)
