# `output F: v, pr, rho every 100` (examples/sph_dam_break.part): VTK frames
# of F alone, every 100 steps unless --every says otherwise, holding id, the
# points and those variables only, in the order the set declares them.
# Usage: cmake -DPROGRAM=... -DDIR=... -P check_frames.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../cmake/program_run.cmake)
function(expect_files prefix)
  file(GLOB found RELATIVE ${DIR} ${DIR}/${prefix}*)
  list(SORT found)
  set(wanted ${ARGN})
  list(SORT wanted)
  if(NOT "${found}" STREQUAL "${wanted}")
    message(FATAL_ERROR "${prefix}: expected files ${wanted}, found ${found}")
  endif()
endfunction()

run(--steps 250 --vtk ${DIR}/db)
expect_files(db db_F.pvd db_F_000000.vtu db_F_000100.vtu db_F_000200.vtu)
file(READ ${DIR}/db_F_000100.vtu frame)
string(REGEX MATCHALL "Name=\"[a-z_]+\"" arrays "${frame}")
set(wanted "Name=\"id\";Name=\"v\";Name=\"rho\";Name=\"pr\";Name=\"connectivity\";Name=\"offsets\";Name=\"types\"")
if(NOT "${arrays}" STREQUAL "${wanted}")
  message(FATAL_ERROR "frame arrays: expected ${wanted}, found ${arrays}")
endif()

run(--steps 3 --every 2 --vtk ${DIR}/every)
expect_files(every every_F.pvd every_F_000000.vtu every_F_000002.vtu)
