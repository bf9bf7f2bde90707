# Reliability through the cmc program: each test is one reproduction of a defect or one
# decided rule (cases/README.md "Output folders" and "Numbers", reference/README.md "Log
# axes"), with the exit code it must give and what must be left on disk. Each works in its
# own folder under build/cli-reliability/. cmc_cli_test: validation/validation.cmake.
set(CMC_REL ${CMAKE_BINARY_DIR}/cli-reliability)
set(CMC_BIN $<TARGET_FILE:cmc>)
set(CMC_WAVY ${CMAKE_SOURCE_DIR}/cases/validation/westergaard.toml)
set(CMC_HARDWALL ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load-hardwall.toml)
set(CMC_ROUGH ${CMAKE_SOURCE_DIR}/cases/challenge/reference-load.toml)
set(CMC_SPHERE ${CMAKE_SOURCE_DIR}/cases/validation/hertz-free.toml)
# A fresh folder for test NAME, as the shell variable D.
function(cmc_rel_test name command)
  cmc_cli_test(reliability.${name} "D=${CMC_REL}/${name}; rm -rf $D && mkdir -p $D && cd $D && ${command}")
endfunction()

# ---- every writer refuses special files and links as targets (grid/FilePaths.hpp): exit 2,
# the target left as it was, no temporary file left beside it.
cmc_rel_test(surface_write_fifo "mkfifo f && ${CMC_BIN} surface ${CMC_WAVY} --write f >/dev/null 2>err; test $? -eq 2 && test -p f && grep -q 'f: is a FIFO' err && test $(ls -A | wc -l) -eq 2")
cmc_rel_test(surface_write_link "ln -s target.h5 l.h5 && ${CMC_BIN} surface ${CMC_WAVY} --write l.h5 >/dev/null 2>err; test $? -eq 2 && test -L l.h5 && test ! -e target.h5 && grep -q 'is a symbolic link (to target.h5)' err")
cmc_rel_test(surface_write_folder "mkdir d && ${CMC_BIN} surface ${CMC_WAVY} --write d >/dev/null 2>err; test $? -eq 2 && test -d d && test -z \"$(ls -A d)\" && grep -q 'd: is a folder' err")
cmc_rel_test(run_curve_fifo "mkfifo gap_distribution.csv && ${CMC_BIN} reference --run-curve ${CMAKE_SOURCE_DIR}/tests/data/run_curve_spec.toml --out gap_distribution.csv 2>err; test $? -eq 2 && test -p gap_distribution.csv && test $(ls -A | wc -l) -eq 2")
cmc_rel_test(run_summary_fifo "mkdir o && mkfifo o/summary.json && ${CMC_BIN} run ${CMC_WAVY} --set grid.nx=64 --out o --quiet 2>err; test $? -eq 2 && test -p o/summary.json && test ! -e o/result.h5")
cmc_rel_test(check_out_fifo "mkfifo f && ${CMC_BIN} check ${CMAKE_SOURCE_DIR}/reference/challenge/contact_area_vs_pressure.csv --quantity contact_area_vs_pressure --out f >/dev/null 2>err; test $? -eq 2 && test -p f && grep -q 'expected a folder' err")
# Decided: cmc replaces only its own results; a foreign summary.json is left as it is.
cmc_rel_test(foreign_summary "mkdir o && echo '{\"mine\": 1}' > o/summary.json && ${CMC_BIN} run ${CMC_WAVY} --set grid.nx=64 --out o --quiet 2>err; test $? -eq 2 && grep -q 'not a cmc run summary' err && grep -q mine o/summary.json")

# ---- cmc validate: two cases of one case.name would share DIR/<name>/ and a table label.
cmc_rel_test(validate_same_name "${CMC_BIN} validate ${CMC_SPHERE} ${CMAKE_SOURCE_DIR}/cases/validation/hertz-periodic.toml --set case.name=same --set grid.n=32 --out o --quiet >/dev/null 2>err; test $? -eq 2 && grep -q \"name 'same' is also the name of ${CMC_SPHERE}\" err && test ! -e o")

# ---- cmc check on log axes: a contact fraction of 0 (or -0.01) where the reference has a
# positive one fails, naming the rows; it was left out and interpolated across, and passed.
set(CMC_AREA_REF ${CMAKE_SOURCE_DIR}/reference/challenge/contact_area_vs_pressure.csv)
set(CMC_AREA_ROWS "grep -v '^#' ${CMC_AREA_REF} | sed 1d")
cmc_rel_test(check_zeros_on_log_axis "{ echo pressure_Pa,contact_fraction; ${CMC_AREA_ROWS} | awk -F, '{print $1 \",\" (NR % 2 == 0 && NR < 13 ? 0 : $2)}'; } > p.csv && ${CMC_BIN} check p.csv --quantity contact_area_vs_pressure >out; test $? -eq 5 && grep -q 'FAIL: 6 row(s) of the prediction give the relative contact area <= 0' out && grep -q 'lines 3, 5, 7, 9, 11, ...' out")
cmc_rel_test(check_negative_on_log_axis "{ echo pressure_Pa,contact_fraction; ${CMC_AREA_ROWS} | awk -F, '{print $1 \",\" (NR == 7 ? -0.01 : $2)}'; } > p.csv && ${CMC_BIN} check p.csv --quantity contact_area_vs_pressure >out; test $? -eq 5 && grep -q '(line 8 of p.csv)' out")

# ---- cmc refine: a --set of grid.n ran every grid at that size, labelled n16 and n32, and
# reported a change of 0; a bad grid size was not named.
cmc_rel_test(refine_grid_override "${CMC_BIN} refine ${CMC_HARDWALL} --grids 16 32 --set grid.n=999 --out o 2>err; test $? -eq 2 && grep -q -- '--set grid.n=999 overrides --grids 16 32' err && test ! -e o")
cmc_rel_test(refine_bad_grid_named "${CMC_BIN} refine ${CMC_HARDWALL} --grids 32 abc --out o 2>err; test $? -eq 2 && grep -q \"'abc' is neither a whole number\" err && test ! -e o")

# ---- numbers that overflow in reduced units are bad input naming the key (scene/SceneChecks.hpp);
# each used to end "converged" with Infinity, NaN or impossible numbers, exit 0.
cmc_rel_test(overflow_grid_size "${CMC_BIN} run ${CMC_SPHERE} --set grid.n=32 --set grid.size=1e308 --set surface.radius=1e308 --out o --quiet 2>err; test $? -eq 2 && grep -q '\\[grid\\] size = 1e+308 m' err && test ! -e o")
cmc_rel_test(overflow_rms_gradient "${CMC_BIN} surface ${CMC_ROUGH} --set grid.n=32 --set surface.rms_gradient=1e308 --write h.h5 >/dev/null 2>err; test $? -eq 2 && grep -q '\\[surface\\] rms_gradient: the surface.s heights are not finite' err && test ! -e h.h5")
cmc_rel_test(underflow_radius "${CMC_BIN} run ${CMC_SPHERE} --set grid.n=32 --set surface.radius=1e-300 --out o --quiet 2>err; test $? -eq 2 && grep -q '\\[surface\\] radius = 1e-300 m, which is 1e-297 in reduced units' err && test ! -e o")
cmc_rel_test(overflow_modulus "${CMC_BIN} run ${CMC_ROUGH} --set grid.n=32 --set material.contact_modulus=1e308 --out o --quiet 2>err; test $? -eq 2 && grep -q '\\[interaction\\] work_of_adhesion = 0.05 J/m^2, which is 5e-306' err && test ! -e o")
cmc_rel_test(overflow_tabor "${CMC_BIN} run ${CMAKE_SOURCE_DIR}/cases/challenge/tabor-sweep.toml --set grid.n=32 --set interaction.tabor=1e308 --out o --quiet 2>err; test $? -eq 2 && grep -q '\\[interaction\\] tabor = 1e+308 sets the range rho' err && test ! -e o")

# ---- a truncated step file of an interrupted run is refused on --resume like a missing one
# (it was solved again, failed with exit 4, wrote a "failed" summary.json and left a
# .result.h5.tmpPID per try): exit 2, nothing written, no temporary file.
set(CMC_STEPS "${CMC_BIN} run ${CMC_HARDWALL} --set grid.n=64 --set loading.values=[1e4,2e4,4e4,8e4,16e4] --out o --quiet")
cmc_rel_test(resume_truncated_step "CMC_TEST_KILL_AT=step:4 ${CMC_STEPS}; test -e o/.partial/step_0003.h5 && truncate -s 1000 o/.partial/step_0003.h5 && ${CMC_STEPS} --resume 2>err; test $? -eq 2 && grep -q 'step_0003.h5) are damaged: not a readable HDF5 file' err && test ! -e o/summary.json && test -z \"$(ls -A o o/.partial | grep tmp)\" && ${CMC_STEPS} && grep -q '\"status\" : \"converged\"' o/summary.json")

# A step file of another run (here a 32² run's, in a 64² run's .partial/) was merged into
# result.h5 and the run ended "converged": refused like a damaged one.
cmc_rel_test(resume_step_of_other_grid "CMC_TEST_KILL_AT=step:4 ${CMC_STEPS}; CMC_TEST_KILL_AT=step:4 ${CMC_BIN} run ${CMC_HARDWALL} --set grid.n=32 --set loading.values=[1e4,2e4,4e4,8e4,16e4] --out x --quiet; cp x/.partial/step_0002.h5 o/.partial/step_0002.h5 && ${CMC_STEPS} --resume 2>err; test $? -eq 2 && grep -q \"step_0002/pressure is 32 x 32 points where the run has 64 x 64\" err && test ! -e o/summary.json")

# ---- input errors that were run failures (exit 4 after a solve, or with an internal name)
# are exit 2 before any solve (the case read, its scene built, or cmc validate checking its
# reference), naming the key and what is expected; nothing is made.
cmc_rel_test(self_affine_one_point "${CMC_BIN} run ${CMC_ROUGH} --set grid.n=1 --out o 2>err; test $? -eq 2 && grep -q 'a grid of at least 2 x 2 points for a self-affine surface' err && test ! -e o")
cmc_rel_test(wavy_one_point "${CMC_BIN} run ${CMC_WAVY} --set grid.nx=1 --out o 2>err; test $? -eq 2 && grep -q '\\[surface\\] wavelength: expected at least 2 grid points a wavelength (here 1)' err && test ! -e o")
cmc_rel_test(tabor_without_curvature "${CMC_BIN} run ${CMAKE_SOURCE_DIR}/cases/challenge/tabor-sweep.toml --set grid.n=2 --out o 2>err; test $? -eq 2 && grep -q '\\[interaction\\] tabor: expected a surface with a radius of curvature' err && test ! -e o")
cmc_rel_test(reference_on_wrong_surface "${CMC_BIN} validate ${CMC_SPHERE} --set validation.reference=westergaard --out o 2>err; test $? -eq 2 && grep -q '\\[validation\\] reference: \"westergaard\" compares a wavy1d surface' err && test ! -e o")
cmc_rel_test(quantity_not_in_reference "${CMC_BIN} validate ${CMAKE_SOURCE_DIR}/cases/validation/jkr-tabor5.slow.toml --set 'validation.check=[{quantity=\"penetration\", tolerance=0.1}]' --out o 2>err; test $? -eq 2 && grep -q 'quantity: expected \"force\" or \"pulloff\" (what reference \"jkr\" has), got \"penetration\"' err && test ! -e o")

# ---- decided: cmc reference --run-curve writes only curves cmc check reads as references
# (named NAME.csv, x strictly monotonic, positive on log axes); it wrote ones check refused.
set(CMC_SPEC ${CMAKE_SOURCE_DIR}/tests/data/run_curve_spec.toml)
cmc_rel_test(run_curve_name "${CMC_BIN} reference --run-curve ${CMC_SPEC} --out x.csv 2>err; test $? -eq 2 && grep -q 'expected a file named gap_distribution.csv' err && test ! -e x.csv")
cmc_rel_test(run_curve_log_axis "sed 's/^representation = .*/representation = \"log-log\"/' ${CMC_SPEC} > s.toml && ${CMC_BIN} reference --run-curve s.toml --out gap_distribution.csv 2>err; test $? -eq 2 && grep -q 'is not positive on the log axes' err && test ! -e gap_distribution.csv")
cmc_rel_test(run_curve_unsorted "sed 's/values = \\[1e-09, 2.5e-09\\]/values = [2.5e-09, 1e-09, 3e-09]/; s/values = \\[3.0, -0.0\\]/values = [3.0, 1.0, 2.0]/' ${CMC_SPEC} > s.toml && ${CMC_BIN} reference --run-curve s.toml --out gap_distribution.csv 2>err; test $? -eq 2 && grep -q 'non-monotonic abscissa' err && test ! -e gap_distribution.csv")

# ---- decided: files given to cmc check say what they are (they all read "no such file").
cmc_rel_test(check_input_kinds "mkdir d && ln -s loop loop && for f in d loop /dev/zero; do ${CMC_BIN} check $f --quantity contact_area_vs_pressure 2>>err; test $? -eq 2 || exit 1; done; grep -q 'd: is a folder, expected a file' err && grep -q 'loop: is a symbolic link that cannot be resolved' err && grep -q '/dev/zero: is a character device, expected a file on disk' err")
# ---- decided: .partial/ is cmc's working folder: a file put there goes with it.
cmc_rel_test(partial_is_cmcs "${CMC_BIN} run ${CMC_WAVY} --set grid.nx=64 --out o --quiet && mkdir -p o/.partial && echo mine > o/.partial/mine.txt && ${CMC_BIN} run ${CMC_WAVY} --set grid.nx=64 --out o --quiet && test ! -e o/.partial")
# ---- decided: --resume with nothing to resume starts afresh and says so; on a finished run
# (another grid here) it is refused, the finished run left as it is.
cmc_rel_test(resume_nothing "${CMC_BIN} run ${CMC_WAVY} --set grid.nx=64 --out o --resume 2>err >/dev/null; test $? -eq 0 && grep -q 'nothing to resume in o (no checkpoint): starting afresh' err && ${CMC_BIN} run ${CMC_WAVY} --set grid.nx=128 --out o --resume --quiet 2>err; test $? -eq 2 && grep -q 'o holds a finished run' err && grep -q '\"nx\" : 64' o/summary.json")
# ---- decided: an option is not a value (run --out --quiet made a folder named --quiet).
cmc_rel_test(option_as_value "${CMC_BIN} run ${CMC_WAVY} --out --quiet 2>err; test $? -eq 2 && grep -q -- '--out needs a value, got the option --quiet' err && test -z \"$(ls -A | grep -v err)\"")
# ---- decided: CMC_THREADS must be a whole number from 1 (it was ignored when malformed).
cmc_rel_test(threads_variable "for t in abc 0 -1; do CMC_THREADS=$t ${CMC_BIN} run ${CMC_WAVY} --out o 2>>err; test $? -eq 2 || exit 1; done; test $(grep -c 'environment variable CMC_THREADS' err) -eq 3 && test ! -e o")
# The FFTW wisdom cache ($CMC_FFTW_WISDOM, kept by the measuring planners) follows the same
# rule: a FIFO there is left as it is, with a warning, and the run goes on.
cmc_rel_test(wisdom_fifo "mkfifo w && CMC_FFTW_PLANNER=measure CMC_FFTW_WISDOM=$D/w ${CMC_BIN} run ${CMC_WAVY} --set grid.nx=64 --out o --quiet 2>err; test $? -eq 0 && test -p w && grep -q 'FFTW wisdom not saved: .*w: is a FIFO' err")
# cmc refine checks every file it will write before the first grid runs.
cmc_rel_test(refine_output_fifo "mkdir o && mkfifo o/refinement.md && ${CMC_BIN} refine ${CMC_HARDWALL} --grids 16 32 --out o 2>err; test $? -eq 2 && test -p o/refinement.md && test ! -e o/n16")
# A Dugdale smoothing of 2 h0 or more was exit 4 with an internal name.
cmc_rel_test(dugdale_smoothing "${CMC_BIN} run ${CMAKE_SOURCE_DIR}/cases/validation/maugis-dugdale-lambda1.toml --set grid.n=32 --set interaction.smoothing=1 --out o 2>err; test $? -eq 2 && grep -q '\\[interaction\\] smoothing = 1 m: expected a width below 2 h0' err && test ! -e o")

# ---- a single-value option given twice is refused, naming it (the first one silently won:
# --tolerance 10 --tolerance 0.01 passed a prediction twice the answer).
cmc_rel_test(option_given_twice "${CMC_BIN} check ${CMC_AREA_REF} --quantity contact_area_vs_pressure --tolerance 10 --tolerance 0.01 >out 2>err; test $? -eq 2 && grep -q -- '--tolerance is given twice' err && test ! -s out && ${CMC_BIN} run ${CMC_WAVY} --set grid.nx=64 --out a -o b 2>err; test $? -eq 2 && grep -q -- '-o is given twice' err && test ! -e a && test ! -e b")
# ---- messages say what is wrong: a regular file where a folder belongs ("is not a regular
# file" before), checked before anything is printed; a FAIL for want of coverage says so first
# (its first line read "inside the reference's error band").
cmc_rel_test(out_is_a_file "echo mine > f && ${CMC_BIN} check ${CMC_AREA_REF} --quantity contact_area_vs_pressure --out f >out 2>err; test $? -eq 2 && grep -q 'f: is a regular file, expected a folder' err && test ! -s out && test \"$(cat f)\" = mine")
cmc_rel_test(check_fail_reason_first "{ echo pressure_Pa,contact_fraction; ${CMC_AREA_ROWS} | awk -F, 'NR == 5 || NR == 6 {print $1 \",\" $2}'; } > p.csv && ${CMC_BIN} check p.csv --quantity contact_area_vs_pressure >out; test $? -eq 5 && grep -q '^verdict *FAIL: the prediction covers' out && grep -q '^ *though inside the reference.s error band' out")
