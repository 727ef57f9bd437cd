# CMake functions that compile a .part model with partc as part of a build.
#
#   partc_add_model(<target> <file.part> [PARTC_FLAGS flag...])
#       an executable: the generated model plus its command-line driver
#       (PARTC_FLAGS: more of partc's options, e.g. --profile).
#   partc_add_model_library(<target> <file.part> [PARTC_FLAGS flag...])
#       an INTERFACE library whose include path holds <file>.hpp, the
#       generated model class, for C++ code that drives the model itself.
#
# Both regenerate the C++ whenever the .part file, a module it uses (partc
# writes a depfile) or partc changes. partc_add_model reuses the precompiled
# runtime headers of target partc_model_pch when the build has it
# (PARTC_MODEL_PCH, the default).
# PARTC_EXECUTABLE must name partc (a path or a generator expression).

function(_partc_generate part_file out_file extra_flags)
  get_filename_component(part_abs ${part_file} ABSOLUTE)
  get_filename_component(out_dir ${out_file} DIRECTORY)
  file(MAKE_DIRECTORY ${out_dir})
  add_custom_command(
    OUTPUT ${out_file}
    COMMAND ${PARTC_EXECUTABLE} ${part_abs} -o ${out_file} --depfile ${out_file}.d ${extra_flags}
    DEPENDS ${part_abs} ${PARTC_EXECUTABLE_DEPENDS}
    DEPFILE ${out_file}.d
    COMMENT "partc ${part_file}"
    VERBATIM)
endfunction()

if(NOT DEFINED PARTC_EXECUTABLE_DEPENDS AND TARGET partc)
  set(PARTC_EXECUTABLE_DEPENDS partc)
endif()

function(partc_add_model target part_file)
  cmake_parse_arguments(PARSE_ARGV 2 model "" "" "PARTC_FLAGS")
  get_filename_component(stem ${part_file} NAME_WE)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${target}_gen/${stem}.cpp)
  _partc_generate(${part_file} ${out} "--main;${model_PARTC_FLAGS}")
  add_executable(${target} ${out})
  target_link_libraries(${target} PRIVATE partc_runtime)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Werror)
  if(TARGET partc_model_pch)
    target_precompile_headers(${target} REUSE_FROM partc_model_pch)
  endif()
endfunction()

function(partc_add_model_library target part_file)
  cmake_parse_arguments(PARSE_ARGV 2 model "" "" "PARTC_FLAGS")
  get_filename_component(stem ${part_file} NAME_WE)
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/${target}_gen)
  set(out ${dir}/${stem}.hpp)
  _partc_generate(${part_file} ${out} "${model_PARTC_FLAGS}")
  add_custom_target(${target}_generate DEPENDS ${out})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_generate)
  target_include_directories(${target} INTERFACE ${dir})
  target_link_libraries(${target} INTERFACE partc_runtime)
endfunction()
