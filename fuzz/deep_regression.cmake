# ctest's fuzz.<reader>.deep (cmake -DREADER=<reader> -DTARGET=<its regression
# driver> -DDIR=<a scratch folder> -P): the input that once crashed the CLI,
# 100,000 nested brackets (in a render scene file's camera.path, SIGSEGV in
# the recursive code that copies and prints JSON values), written here rather
# than kept in the repository, fed to the reader's fuzz target, which must
# refuse it cleanly (its depth is checked before it is parsed).
string(REPEAT "[" 100000 open)
string(REPEAT "]" 100000 close)
set(deep "${open}${close}")
if(READER STREQUAL "cli_scene")
  set(deep "{\"particles\": \"f.bgeo\", \"camera\": {\"path\": [{\"time\": 0, \"eye\": ${deep}}]}}")
elseif(READER STREQUAL "splishsplash")
  set(deep "{\"RigidBodies\": ${deep}}")
endif()
file(MAKE_DIRECTORY ${DIR})
file(WRITE ${DIR}/${READER}_deep.json "${deep}")
execute_process(COMMAND ${TARGET} ${DIR}/${READER}_deep.json RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fuzz_${READER}: 100,000 nested brackets: exit ${rc}")
endif()
