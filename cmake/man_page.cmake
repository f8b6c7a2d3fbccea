# Writes the man page of one tool from its --help with help2man (cmake -P; cmake/Install.cmake):
#   -DTOOL=path/to/vdb_x -DVERSION=0.1.0 -DHELP2MAN=/usr/bin/help2man -DOUTPUT=vdb_x.1
# The page's NAME line is the tool's description (the first line of --help) up to its first colon.
execute_process(COMMAND ${TOOL} --help OUTPUT_VARIABLE help RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${TOOL} --help failed: ${status}")
endif()
string(REGEX MATCH "^[^\n]*" description "${help}")
string(REGEX REPLACE ":.*$|\\.$" "" description "${description}")
string(STRIP "${description}" description)
string(REPLACE "§" "section " description "${description}")  # help2man would encode --name twice
string(SUBSTRING "${description}" 0 1 first)
string(SUBSTRING "${description}" 1 -1 rest)
string(TOLOWER "${first}" first)
# help2man reads --help in the C locale unless told (the § of the descriptions).
execute_process(COMMAND ${HELP2MAN} --no-info --no-discard-stderr --locale=C.UTF-8 "--version-string=${VERSION}"
                        "--name=${first}${rest}" "--source=vdbappear ${VERSION}" "--manual=vdbappear tools"
                        --output=${OUTPUT}.tmp ${TOOL}
                RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "help2man failed on ${TOOL}: ${status}")
endif()
file(RENAME ${OUTPUT}.tmp ${OUTPUT})
