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

# scripts/tabor_sweep.sh's options: a --grid that is not a number, a --tabor value that is not
# a positive number and an empty --tabor are refused with exit 2 and a message naming the
# option, before anything is built or run.
add_test(NAME tabor_sweep.refusals COMMAND sh -c "S=${CMAKE_SOURCE_DIR}/scripts/tabor_sweep.sh; \
  $S --grid abc 2>&1 >/dev/null | grep -q -- '--grid needs a number' && { $S --grid abc >/dev/null 2>&1; test $? -eq 2; } && \
  $S --tabor abc 2>&1 >/dev/null | grep -q -- \"--tabor: 'abc' is not a positive number\" && { $S --tabor abc >/dev/null 2>&1; test $? -eq 2; } && \
  $S --tabor 0.0 2>&1 >/dev/null | grep -q -- \"--tabor: '0.0' is not a positive number\" && \
  $S --tabor '' 2>&1 >/dev/null | grep -q -- '--tabor needs a list' && { $S --tabor '' >/dev/null 2>&1; test $? -eq 2; }")
set_tests_properties(tabor_sweep.refusals PROPERTIES LABELS quick)
# scripts/test.sh reads its arguments before it installs or builds anything: --help prints its
# header, an argument that is not one of ctest's selections is refused (exit 2; ctest would
# ignore it and run everything).
add_test(NAME test_sh.arguments COMMAND sh -c "T=${CMAKE_SOURCE_DIR}/scripts/test.sh; \
  $T --help | head -1 | grep -q '^The test command' && { $T --bogus 2>${CMAKE_BINARY_DIR}/test_sh.err; test $? -eq 2; } && \
  grep -q \"unknown argument '--bogus'\" ${CMAKE_BINARY_DIR}/test_sh.err && { $T -R 2>/dev/null; test $? -eq 2; }")
set_tests_properties(test_sh.arguments PROPERTIES LABELS quick TIMEOUT 30)

# The analysis package (python/cmc/analysis: refinement, family errors, best estimates, the
# extremum), each formula against a hand-computed case.
add_test(NAME analysis.unit COMMAND /usr/bin/python3 -m pytest -q -p no:cacheprovider ${CMAKE_SOURCE_DIR}/tests/analysis)
set_tests_properties(analysis.unit PROPERTIES LABELS "quick;python")
# The case-file reader of the Python scripts (python/cmc/case_files.py): bases merged as the
# program merges them, and the challenge cases read through theirs.
add_test(NAME case_files.python COMMAND /usr/bin/python3 -m pytest -q -p no:cacheprovider ${CMAKE_SOURCE_DIR}/tests/case_files)
set_tests_properties(case_files.python PROPERTIES LABELS "quick;python")

# The report scripts on synthetic inputs (Debian's python3 with matplotlib/h5py).
add_test(NAME reports.selftest COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/reports/selftest.py)
set_tests_properties(reports.selftest PROPERTIES LABELS "quick;python")
# The README's figure is drawn from the stored references alone, into a scratch file here.
add_test(NAME reports.readme_figure
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/readme_figure.py
                 --out ${CMAKE_BINARY_DIR}/readme_figure_test.png)
set_tests_properties(reports.readme_figure PROPERTIES LABELS "quick;python")
# scripts/scaled_family.py's realizations: --seed, and error bars over every
# stored realization (tests/scaled_family_test.py says what each checks; no cmc run).
foreach(t seed_flag reestimate conditions bands own_refinement)
  add_test(NAME scaled_family.${t} COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/scaled_family_test.py ${t})
  set_tests_properties(scaled_family.${t} PROPERTIES LABELS "quick;python")
endforeach()

# cmc surface prints R_c = 1/(rms line-scan curvature) (SurfaceStats.hpp). Two checks
# against values derived from the surface's definition, not from an earlier run:
# - a known case, the 1-D wavy surface h(x) = h0 (1 - cos 2 pi x/lambda) of
#   westergaard.toml (h0 = 1 um, lambda = 1 mm): <h_xx^2> = h0^2 k^4 / 2 and h_yy = 0,
#   so kappa_rms = sqrt(<h_xx^2>/2) = h0 k^2 / 2 and R_c = lambda^2 / (2 pi^2 h0)
#   = 0.0506606 m (spectral derivatives: exact to the 6 printed digits).
add_test(NAME cli.surface_wavy COMMAND cmc surface ${CMAKE_SOURCE_DIR}/cases/validation/westergaard.toml)
set_tests_properties(cli.surface_wavy PROPERTIES LABELS quick PASS_REGULAR_EXPRESSION "R_c +0\\.0506606 m")
# - the challenge surface's 256² preview keeps the modes |kx|, |ky| < 128 of the band
#   (SelfAffine.hpp). Summing (kx^4 + ky^4)/2 S(k) over the kept and over all modes of
#   the problem definition's spectrum S(k) (eq. 1: flat below |k| = 5, |k|^-3.6 up to
#   |k| = 1000) gives R_c(256)/R_c(full) = 10.52, and R_c(full) = 60.1 nm (problem
#   definition), so R_c(256) = 632 nm. The complex-Gaussian mode amplitudes scatter
#   this ratio by 0.4 % (1 sigma, Monte Carlo over 100 draws of the amplitudes); the
#   band is +-2 % (5 sigma): 619-645 nm. Measured: 627.8 nm.
add_test(NAME cli.surface COMMAND cmc surface ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load.toml --set grid.n=256)
set_tests_properties(cli.surface PROPERTIES LABELS quick
                     PASS_REGULAR_EXPRESSION "R_c +6\\.(19|2[0-9]|3[0-9]|4[0-4])[0-9]*e-07 m")

# cmc refine: a three-grid study of the hard-wall challenge case on 64², 128², 256²
# (about a second). It must write the table with an observed order in the penetration
# row, and a second call must reuse all three finished grids instead of rerunning them.
# A command-line check: a shell command line that must exit 0 (label quick).
function(cmc_cli_test name command)
  add_test(NAME ${name} COMMAND sh -c "${command}")
  set_tests_properties(${name} PROPERTIES LABELS quick)
endfunction()
set(CMC_REFINE_OUT ${CMAKE_BINARY_DIR}/cli-refine)
set(CMC_REFINE_CMD "$<TARGET_FILE:cmc> refine ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml --grids 64 128 256 --out ${CMC_REFINE_OUT}")
cmc_cli_test(cli.refine "rm -rf ${CMC_REFINE_OUT} && ${CMC_REFINE_CMD} --quiet >/dev/null && grep -Eq '^[|] penetration [|].*[|] [0-9]+[.][0-9]+ [|]$' ${CMC_REFINE_OUT}/refinement.md && test \"$(${CMC_REFINE_CMD} 2>&1 >/dev/null | grep -c 'finished earlier')\" -eq 3")
# Grids out of order are bad input (exit code 2), and nothing is run.
cmc_cli_test(cli.refine_bad_grids "$<TARGET_FILE:cmc> refine ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml --grids 256 128 --out ${CMAKE_BINARY_DIR}/cli-refine-bad; test $? -eq 2 && test ! -e ${CMAKE_BINARY_DIR}/cli-refine-bad")

# The challenge itself, at 256² (about 1 s each; checks in validation/challenge_smoke.cmake):
# hard wall (converged, kappa = a_r E* g / p in [1.7, 2.3]) and with the challenge's
# adhesion (converged, tension present and bounded by w/rho, more contact than the hard wall).
foreach(kind hardwall adhesive)
  if(kind STREQUAL "hardwall")
    set(case_file ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml)
  else()
    set(case_file ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load.toml)
  endif()
  add_test(NAME challenge.${kind}_256
           COMMAND ${CMAKE_COMMAND} -DCMC=$<TARGET_FILE:cmc> -DCASE=${case_file} -DKIND=${kind}
                   -DOUT=${CMAKE_BINARY_DIR}/challenge/${kind}_256 -DHARDWALL=${CMAKE_BINARY_DIR}/challenge/hardwall_256
                   -P ${CMAKE_SOURCE_DIR}/validation/challenge_smoke.cmake)
  set_tests_properties(challenge.${kind}_256 PROPERTIES LABELS challenge TIMEOUT 120)
endforeach()
set_tests_properties(challenge.hardwall_256 PROPERTIES FIXTURES_SETUP challenge_hardwall_256)
set_tests_properties(challenge.adhesive_256 PROPERTIES FIXTURES_REQUIRED challenge_hardwall_256)

# cmc reference --run-curve (scripts/challenge_reference.py's formatter): a spec becomes a
# curve in the reference format, metadata in make_run_curve's order, numbers "%.12e" (-0
# written as 0), the extra keys after the provenance. A spec with a key missing is bad
# input: exit 2, no file. (The file must be named after the curve: reference/README.md.)
set(CMC_RUN_CURVE_OUT ${CMAKE_BINARY_DIR}/cli-run-curve/gap_distribution.csv)  # named after the curve
cmc_cli_test(cli.reference_run_curve "rm -f ${CMC_RUN_CURVE_OUT} && $<TARGET_FILE:cmc> reference --run-curve ${CMAKE_SOURCE_DIR}/tests/data/run_curve_spec.toml --out ${CMC_RUN_CURVE_OUT} && grep -q '^# source: cmc run$' ${CMC_RUN_CURVE_OUT} && grep -A1 '^# cmc_version: 0.1.0$' ${CMC_RUN_CURVE_OUT} | grep -q '^# case_file: ' && grep -q '^# sampling: two points$' ${CMC_RUN_CURVE_OUT} && grep -q '^2.500000000000e-09,0.000000000000e+00$' ${CMC_RUN_CURVE_OUT}")
cmc_cli_test(cli.reference_run_curve_bad_spec "printf 'name = \"x\"\\n' > ${CMAKE_BINARY_DIR}/bad-spec.toml; $<TARGET_FILE:cmc> reference --run-curve ${CMAKE_BINARY_DIR}/bad-spec.toml --out ${CMAKE_BINARY_DIR}/bad-curve.csv; test $? -eq 2 && test ! -e ${CMAKE_BINARY_DIR}/bad-curve.csv")

# Same bits on every rerun: the adhesive challenge at 256² (every grid point bistable, so
# round-off picks among local minima) run twice on two threads into fresh folders, with
# the FFTW wisdom file removed before each run and the planner left at its default (the
# wisdom built in at build time). Every summary.json value and result.h5 dataset must be
# identical (scripts/compare_runs.py). Fails with CMC_FFTW_PLANNER=measure whenever the
# two plannings pick different algorithms.
set(CMC_RERUN ${CMAKE_BINARY_DIR}/rerun)
set(CMC_RERUN_ONE "rm -f ${CMC_RERUN}/wisdom && CMC_THREADS=2 CMC_FFTW_WISDOM=${CMC_RERUN}/wisdom $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load.toml --set grid.n=256 --quiet --out")
cmc_cli_test(rerun.same_bits "rm -rf ${CMC_RERUN} && mkdir -p ${CMC_RERUN} && ${CMC_RERUN_ONE} ${CMC_RERUN}/a && ${CMC_RERUN_ONE} ${CMC_RERUN}/b && /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/compare_runs.py ${CMC_RERUN}/a ${CMC_RERUN}/b")
set_tests_properties(rerun.same_bits PROPERTIES LABELS "quick;python")
# A planner name cmc does not know is an error that names the variable, before any output.
cmc_cli_test(cli.bad_fft_planner "rm -rf ${CMAKE_BINARY_DIR}/bad-planner; CMC_FFTW_PLANNER=bogus $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml --set grid.n=64 --out ${CMAKE_BINARY_DIR}/bad-planner 2>&1 | grep -q 'CMC_FFTW_PLANNER: expected builtin' && test ! -e ${CMAKE_BINARY_DIR}/bad-planner")

# Progress in a log (stderr a pipe, as under ctest or a batch system): with
# CMC_PROGRESS_EVERY=0 every line the solver reports is printed, each on its own line;
# a malformed value is refused (exit 2, naming the variable) before any output is made.
add_test(NAME cli.progress_in_log
         COMMAND sh -c "rm -rf ${CMAKE_BINARY_DIR}/cli_progress && CMC_PROGRESS_EVERY=0 $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load.toml --set grid.n=128 --out ${CMAKE_BINARY_DIR}/cli_progress 2>&1 | cat")
# The quasi-static solver (this case) reports its outer steps and tension change, the
# hard-wall solver its residual.
set_tests_properties(cli.progress_in_log PROPERTIES LABELS quick
                     PASS_REGULAR_EXPRESSION "\n  step 0/1  iteration +[0-9]+  outer step +[0-9]+  tension change [0-9.e+-]+  elapsed +[0-9.]+ s\n")
# ... and inside each outer step its Polonsky-Keer solve's residual (the first, hard-wall
# solve takes minutes on 8192²: the log shows the run is alive).
add_test(NAME cli.progress_inner_solve
         COMMAND sh -c "rm -rf ${CMAKE_BINARY_DIR}/cli_progress_inner && CMC_PROGRESS_EVERY=0 $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load.toml --set grid.n=128 --out ${CMAKE_BINARY_DIR}/cli_progress_inner 2>&1 | cat")
set_tests_properties(cli.progress_inner_solve PROPERTIES LABELS quick
                     PASS_REGULAR_EXPRESSION "\n  step 0/1  iteration +0  outer step +1  Polonsky-Keer residual [0-9.e+-]+  elapsed +[0-9.]+ s\n")
add_test(NAME cli.progress_in_log_hardwall
         COMMAND sh -c "rm -rf ${CMAKE_BINARY_DIR}/cli_progress_hw && CMC_PROGRESS_EVERY=0 $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml --set grid.n=128 --out ${CMAKE_BINARY_DIR}/cli_progress_hw 2>&1 | cat")
set_tests_properties(cli.progress_in_log_hardwall PROPERTIES LABELS quick
                     PASS_REGULAR_EXPRESSION "\n  step 0/1  iteration +[0-9]+  residual [0-9.e+-]+  elapsed +[0-9.]+ s\n")
add_test(NAME cli.progress_every_malformed
         COMMAND sh -c "rm -rf ${CMAKE_BINARY_DIR}/cli_progress_bad; CMC_PROGRESS_EVERY=-1 $<TARGET_FILE:cmc> run ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load.toml --set grid.n=128 --out ${CMAKE_BINARY_DIR}/cli_progress_bad 2>${CMAKE_BINARY_DIR}/cli_progress_bad.err; rc=$?; grep -q CMC_PROGRESS_EVERY ${CMAKE_BINARY_DIR}/cli_progress_bad.err && test $rc -eq 2 && test ! -e ${CMAKE_BINARY_DIR}/cli_progress_bad")
set_tests_properties(cli.progress_every_malformed PROPERTIES LABELS quick)
# The GPU scripts' CPU half: scripts/gpu/check.sh runs a case through a packed
# build (here a pack of this build's cmc) and prints its line, and scripts/gpu/store.py
# stores that run with its provenance; the stored record must carry the run's own answer.
set(CMC_GPU_SCRIPTS ${CMAKE_BINARY_DIR}/gpu-scripts)
cmc_cli_test(gpu_scripts.check_and_store "rm -rf ${CMC_GPU_SCRIPTS} && mkdir -p ${CMC_GPU_SCRIPTS}/pack/bin && ln -s $<TARGET_FILE:cmc> ${CMC_GPU_SCRIPTS}/pack/bin/cmc && : > ${CMC_GPU_SCRIPTS}/pack/env.sh && CMC_THREADS=1 ${CMAKE_SOURCE_DIR}/scripts/gpu/check.sh --pack ${CMC_GPU_SCRIPTS}/pack --out ${CMC_GPU_SCRIPTS}/out cpu-hardwall:64 | grep -Eq '^cpu-hardwall-64 +[0-9]+ .* converged$' && /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/gpu/store.py --device test --date $(date -u +%F) --store ${CMC_GPU_SCRIPTS}/runs.json ${CMC_GPU_SCRIPTS}/out && /usr/bin/python3 -c \"import json; r = json.load(open('${CMC_GPU_SCRIPTS}/runs.json'))['records']; s = json.load(open('${CMC_GPU_SCRIPTS}/out/runs/cpu-hardwall-64/summary.json')); assert len(r) == 1 and r[0]['tag'] == 'cpu-hardwall-64' and r[0]['a_r'] == s['steps'][0]['contact_fraction'] and r[0]['iterations'] == s['timing']['iterations'], r\"")
set_tests_properties(gpu_scripts.check_and_store PROPERTIES LABELS "quick;python")
# check.sh's tabor:N:MU stage (one point of the Tabor sweep; here on the CPU): the run has
# that mu_T, store.py keeps it as kind tabor_mu<MU> with its mu_T, and a mu_T that is not
# one of the sweep's is refused (exit 2) with the list. The run, a quasi-static one, got a
# solver.max_seconds below check.sh's cap (300 s by default), which its case records; one
# given with --set is kept as given, and no second one is added.
set(CMC_GPU_TABOR ${CMAKE_BINARY_DIR}/gpu-tabor)
cmc_cli_test(gpu_scripts.tabor_stage "rm -rf ${CMC_GPU_TABOR} && mkdir -p ${CMC_GPU_TABOR}/pack/bin && ln -s $<TARGET_FILE:cmc> ${CMC_GPU_TABOR}/pack/bin/cmc && : > ${CMC_GPU_TABOR}/pack/env.sh && CMC_THREADS=1 ${CMAKE_SOURCE_DIR}/scripts/gpu/check.sh --pack ${CMC_GPU_TABOR}/pack --out ${CMC_GPU_TABOR}/out cpu-tabor:64:0.316 | grep -Eq '^cpu-tabor_mu0.316-64 +[0-9]+ .* converged$' && { CMC_THREADS=1 ${CMAKE_SOURCE_DIR}/scripts/gpu/check.sh --pack ${CMC_GPU_TABOR}/pack --out ${CMC_GPU_TABOR}/bad cpu-tabor:64:0.3 2>${CMC_GPU_TABOR}/bad.err; test $? -eq 2; } && grep -q '0.0562 0.1 0.178' ${CMC_GPU_TABOR}/bad.err && /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/gpu/store.py --device test --date $(date -u +%F) --store ${CMC_GPU_TABOR}/runs.json ${CMC_GPU_TABOR}/out && /usr/bin/python3 -c \"import json; r = json.load(open('${CMC_GPU_TABOR}/runs.json'))['records']; s = json.load(open('${CMC_GPU_TABOR}/out/runs/cpu-tabor_mu0.316-64/summary.json')); assert len(r) == 1 and r[0]['kind'] == 'tabor_mu0.316' and r[0]['tabor'] == 0.316 == s['case']['interaction']['tabor'] and r[0]['a_r'] == s['steps'][0]['contact_fraction'], r; v = [float(a.split('=')[1]) for a in open('${CMC_GPU_TABOR}/out/cpu-tabor_mu0.316-64.command').read().split() if a.startswith('solver.max_seconds=')]; assert len(v) == 1 and 0 < v[0] < 300 and s['case']['solver']['max_seconds'] == v[0], v\" && CMC_THREADS=1 ${CMAKE_SOURCE_DIR}/scripts/gpu/check.sh --pack ${CMC_GPU_TABOR}/pack --out ${CMC_GPU_TABOR}/given --set solver.max_seconds=250 cpu-tabor:64:0.316 | grep -Eq '^cpu-tabor_mu0.316-64 +[0-9]+ .* converged$' && test \"$(grep -o 'solver.max_seconds=[0-9.]*' ${CMC_GPU_TABOR}/given/cpu-tabor_mu0.316-64.command)\" = solver.max_seconds=250")
set_tests_properties(gpu_scripts.tabor_stage PROPERTIES LABELS "quick;python")
# scripts/gpu/batch.sh: a stage with its cap and a case override runs through check.sh, and
# its results (the summary, the command with the override) come back in the tarball.
set(CMC_GPU_BATCH ${CMAKE_BINARY_DIR}/gpu-batch)
cmc_cli_test(gpu_scripts.batch "rm -rf ${CMC_GPU_BATCH} && mkdir -p ${CMC_GPU_BATCH}/pack/bin && ln -s $<TARGET_FILE:cmc> ${CMC_GPU_BATCH}/pack/bin/cmc && : > ${CMC_GPU_BATCH}/pack/env.sh && CMC_THREADS=1 ${CMAKE_SOURCE_DIR}/scripts/gpu/batch.sh --deadline 120 --pack ${CMC_GPU_BATCH}/pack --work ${CMC_GPU_BATCH}/check --tar ${CMC_GPU_BATCH}/out.tgz cpu-hardwall:64@60,solver.tolerance=1e-9 | grep -Eq '^cpu-hardwall-64 +[0-9]+ .* converged$' && tar tzf ${CMC_GPU_BATCH}/out.tgz | grep -q '^check/runs/cpu-hardwall-64/summary.json$' && tar xzf ${CMC_GPU_BATCH}/out.tgz -O check/cpu-hardwall-64.command | grep -q 'solver.tolerance=1e-9'")
set_tests_properties(gpu_scripts.batch PROPERTIES LABELS "quick;python")

# The GPU reference plan end to end on the CPU backend at grids / 64 (scripts/gpu/reference_plan.py,
# scripts/gpu/ingest.py): runs, pack, store and references rebuilt into a scratch folder.
add_test(NAME gpu_scripts.reference_plan
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/reference_plan_test.py $<TARGET_FILE:cmc>)
set_tests_properties(gpu_scripts.reference_plan PROPERTIES LABELS "quick;python" TIMEOUT 300)
# What runs on the GPU machine (scripts/gpu/full_plan.sh: reference_plan.py, ensemble.py) runs
# with the checkout's python/ alone and no installed package (python3 -S: no dist-packages, as
# on a machine with Ubuntu's bare python3): their plans print without numpy or h5py.
add_test(NAME gpu_scripts.standard_library_only
         COMMAND sh -c "cd ${CMAKE_BINARY_DIR} && PYTHONPATH=${CMAKE_SOURCE_DIR}/python /usr/bin/python3 -S ${CMAKE_SOURCE_DIR}/scripts/gpu/reference_plan.py --dry-run --scale 64 --cpu | grep -q '^reference_plan: [0-9]* stages' && PYTHONPATH=${CMAKE_SOURCE_DIR}/python /usr/bin/python3 -S ${CMAKE_SOURCE_DIR}/scripts/ensemble.py --dry-run --out ${CMAKE_BINARY_DIR}/stdlib-ensemble --n 64 --kinds tabor --seeds 1 | grep -q ' sweep .*tabor-sweep.toml '")
set_tests_properties(gpu_scripts.standard_library_only PROPERTIES LABELS "quick;python")
# The run store as a trust boundary (tests/gpu_store, one test per file): scripts/gpu/ingest.py,
# store.py, best_estimates.py and reference_plan.py against archives and runs made hostile by
# the tests (names that leave the results folder, special modes, impossible or outlying values,
# corrupt files, failing steps; property tests with hypothesis, a fixed seed); nothing outside a
# scratch store is touched.
foreach(test ingest_paths ingest_trust store_trust store_properties reference_plan_exit)
  add_test(NAME gpu_scripts.${test}
           COMMAND /usr/bin/python3 -m pytest -q -p no:cacheprovider ${CMAKE_SOURCE_DIR}/tests/gpu_store/test_${test}.py)
  set_tests_properties(gpu_scripts.${test} PROPERTIES LABELS "quick;python" TIMEOUT 300
                       ENVIRONMENT "CMC_EXE=$<TARGET_FILE:cmc>")
endforeach()

# The docs check (scripts/check_docs.py; docs/developer/testing.md): every relative link and
# every repository path named in README.md and docs/ exists, and the README's quickstarts run
# (on 64² grids, in a mirror of the repository, with this build's cmc). The checker fails on
# what it is there to catch (tests/check_docs_test.py), and the stored performance tables are
# what scripts/performance_tables.py makes from the stored measurements. docs.comments: no
# comment in the tracked sources names a tracker issue or a date, or says when or by whom it
# was written (history goes in CHANGELOG.md and the commit messages).
add_test(NAME docs.links COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/check_docs.py --links-only)
add_test(NAME docs.comments COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/check_docs.py --comments-only)
add_test(NAME docs.quickstarts
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/check_docs.py --quickstarts-only --build ${CMAKE_BINARY_DIR})
add_test(NAME docs.checker_fails_on_broken_links
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/check_docs_test.py ${CMAKE_BINARY_DIR})
add_test(NAME docs.performance_tables COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/performance_tables.py --check)
set_tests_properties(docs.links docs.comments docs.quickstarts docs.checker_fails_on_broken_links docs.performance_tables
                     PROPERTIES LABELS "quick;python" TIMEOUT 300)
# Size limits (scripts/check_sizes.py): no function over 80 lines and no file over 600 lines in
# solver/, validation/ and every Python file, and the scripts of scripts/ thin commands over the
# package cmc (at most 60 lines on average); the checker fails on what it is there to catch
# (tests/check_sizes_test.py).
add_test(NAME sizes.limits COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/check_sizes.py --max-script-average 60)
add_test(NAME sizes.checker_fails_on_breaches COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/check_sizes_test.py)
set_tests_properties(sizes.limits sizes.checker_fails_on_breaches PROPERTIES LABELS "quick;python")
# No import circle among python/cmc, scripts/ and reports/ (read, not run; the checker first
# finds a circle it was given), and the package type-checks (Debian's mypy, pyproject.toml).
add_test(NAME imports.no_circles COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/import_cycles_test.py)
add_test(NAME python.mypy
         COMMAND /usr/bin/mypy --config-file ${CMAKE_SOURCE_DIR}/pyproject.toml
                 --cache-dir ${CMAKE_BINARY_DIR}/mypy_cache ${CMAKE_SOURCE_DIR}/python/cmc
         WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Every public function of the package carries parameter and return hints (read with ast; the
# checker first finds the gaps of an example it was given), so that mypy checks its body.
add_test(NAME python.type_hints COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/type_hints_test.py)
set_tests_properties(imports.no_circles python.mypy python.type_hints PROPERTIES LABELS "quick;python")
# The README's headline table is what scripts/headline_table.py makes of the stored best estimates.
add_test(NAME docs.headline COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/headline_table.py --check)
set_tests_properties(docs.headline PROPERTIES LABELS "quick;python")
# The stored challenge references hold the best estimates where these decide a row, and `cmc
# check` passes each reference's own curve and fails one 3 % off in a_r.
add_test(NAME challenge_reference.best_estimates
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/challenge_reference_test.py $<TARGET_FILE:cmc>)
set_tests_properties(challenge_reference.best_estimates PROPERTIES LABELS "quick;python")
# Which surface a prediction answers: the held-out surfaces pass the realisation reference and
# fail cmc's own surface's; the ensemble reference fails a curve 10 % off its mean.
add_test(NAME challenge_reference.against
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/ensemble_check_test.py $<TARGET_FILE:cmc>)
set_tests_properties(challenge_reference.against PROPERTIES LABELS "quick;python")
# The seed ensemble end to end at 32²: runs, store (from a folder and an archive, a hostile member
# refused) and the ensemble and realisation references, into a scratch folder.
add_test(NAME ensemble.end_to_end COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/ensemble_test.py $<TARGET_FILE:cmc>)
set_tests_properties(ensemble.end_to_end PROPERTIES LABELS "quick;python" TIMEOUT 300)
# scripts/main.sh --surface FILE --quick on 64² files in the challenge's published layout (HDF5,
# ASCII), made by the test, in a mirror at 64²: runs and report of their own naming the file; a bad
# file exits 2 naming it (tests/surface_main_test.py).
add_test(NAME challenge.surface_file
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/surface_main_test.py ${CMAKE_BINARY_DIR})
set_tests_properties(challenge.surface_file PROPERTIES LABELS "challenge;python" TIMEOUT 600)
