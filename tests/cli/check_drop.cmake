# partc SCENE --drop NAME must write the C++ that SCENE with NAME's use line
# deleted gives: nothing of the dropped effect is left, and nothing else moves.
#
#   cmake -DPARTC=... -DSCENE=dir/scene.part -DNAME=drag -DWORK=dir -P check_drop.cmake
get_filename_component(name ${SCENE} NAME)
get_filename_component(dir ${SCENE} DIRECTORY)
set(work ${WORK}/drop_${NAME})
file(MAKE_DIRECTORY ${work})
# The copy keeps the scene's file name (the C++ cites it) and its folder's modules.
file(READ ${SCENE} text)
string(REGEX REPLACE "\nuse [^\n]*as ${NAME}\n" "\n" without "${text}")
if(without STREQUAL text)
  string(REGEX REPLACE "\nuse [a-z_]+\\.${NAME}[ (][^\n]*\n" "\n" without "${text}")
endif()
if(without STREQUAL text)
  message(FATAL_ERROR "${SCENE} has no use line for ${NAME}")
endif()
file(WRITE ${work}/${name} "${without}")
execute_process(COMMAND ${PARTC} ${SCENE} --drop ${NAME} -o ${work}/dropped.cpp
                RESULT_VARIABLE status ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "partc --drop ${NAME} failed (${status}):\n${err}")
endif()
execute_process(COMMAND ${PARTC} ${work}/${name} --stdlib ${dir} -o ${work}/deleted.cpp
                RESULT_VARIABLE status ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "partc on the scene without ${NAME}'s line failed (${status}):\n${err}")
endif()
file(READ ${work}/dropped.cpp dropped)
file(READ ${work}/deleted.cpp deleted)
if(NOT dropped STREQUAL deleted)
  message(FATAL_ERROR "--drop ${NAME} and deleting its use line give different C++: "
                      "diff ${work}/dropped.cpp ${work}/deleted.cpp")
endif()
# Its parameters (NAME_gamma), comments (effect NAME) and random key (/* NAME */).
foreach(trace "${NAME}_" "effect ${NAME}" "/* ${NAME} */")
  string(FIND "${dropped}" "${trace}" residue)
  if(NOT residue EQUAL -1)
    message(FATAL_ERROR "the C++ without ${NAME} still has '${trace}': ${work}/dropped.cpp")
  endif()
endforeach()
message(STATUS "--drop ${NAME}: byte-identical to the scene without its use line")
