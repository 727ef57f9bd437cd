# After a numerical blow-up the driver writes the last state found finite
# (runtime/partc/io/last_finite.hpp): beside --output by default, or to
# --last-finite; never to --output itself. The file reads back with --input
# and holds the particles of the step the message names.
# Usage: cmake -DBLOWUP=... -DSPH=... -DDIR=... -P check_last_finite.cmake
file(REMOVE_RECURSE ${DIR})
file(MAKE_DIRECTORY ${DIR})
function(expect_run exit regex)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status STREQUAL "${exit}" OR NOT "${out}${err}" MATCHES "${regex}")
    message(FATAL_ERROR "${ARGN}: expected exit ${exit} and '${regex}', got ${status}:\n${out}${err}")
  endif()
endfunction()
function(expect_same a b)
  file(READ ${a} first)
  file(READ ${b} second)
  if(NOT first STREQUAL second)
    message(FATAL_ERROR "${b} differs from ${a}")
  endif()
endfunction()

# blowup.part: x = x / (2 - id) makes particle 2's x inf in step 1.
expect_run(3 "is inf at step 1 \\(set P\\)\nblowup: note: the last state found finite, at step 0, is in [^ ]*/out.last-finite.csv \\(--input reads it back\\)"
           ${BLOWUP} --steps 5 --output ${DIR}/out.csv)
if(EXISTS ${DIR}/out.csv)
  message(FATAL_ERROR "--output was written after a blow-up")
endif()
file(READ ${DIR}/out.last-finite.csv kept)
if(NOT kept STREQUAL "id,p_0,x\n0,0,1\n1,0,1\n2,0,1\n3,0,1\n4,0,1\n")
  message(FATAL_ERROR "the kept state is not step 0's:\n${kept}")
endif()
expect_run(0 "" ${BLOWUP} --quiet --input ${DIR}/out.last-finite.csv --steps 0 --output ${DIR}/back.csv)
expect_same(${DIR}/out.last-finite.csv ${DIR}/back.csv)

# Found late (--check-every 3): the state kept is the last one checked.
expect_run(3 "arose after step 0.*note: the last state found finite, at step 0, is in [^ ]*/late.csv"
           ${BLOWUP} --steps 5 --check-every 3 --last-finite ${DIR}/late.csv)
expect_same(${DIR}/out.last-finite.csv ${DIR}/late.csv)

expect_run(2 "--last-finite ${DIR}/nowhere/kept.csv: directory '${DIR}/nowhere' does not exist"
           ${BLOWUP} --last-finite ${DIR}/nowhere/kept.csv)

# SPH (examples/sph_dam_break.part) at 8 times its CFL number: the pressure
# of one particle overflows within a few steps. Both sets are kept, and read
# back.
expect_run(3 "numerical blow-up: (variable '[a-z_]+' of particle id [0-9]+|observable '[a-z_]+') is (-?inf|nan) at step [0-9]+.*note: the last state found finite, at step [0-9]+, is in [^ ]*/sph.last-finite_F.csv, [^ ]*/sph.last-finite_W.csv"
           ${SPH} --set n=10 --set width=20 --set cfl=2 --steps 300 --output ${DIR}/sph.csv)
expect_run(0 "" ${SPH} --quiet --input F=${DIR}/sph.last-finite_F.csv
           --input W=${DIR}/sph.last-finite_W.csv --steps 0 --output ${DIR}/sph_back.csv)
expect_same(${DIR}/sph.last-finite_F.csv ${DIR}/sph_back_F.csv)
expect_same(${DIR}/sph.last-finite_W.csv ${DIR}/sph_back_W.csv)
