# ctest Docs.PluginReferenceIsCurrent: compares docs/plugins.md with what the built harness
# prints (cmake -DCLI=<shellflow> -DREFERENCE=<docs/plugins.md> -P this file).
execute_process(COMMAND ${CLI} plugins --markdown OUTPUT_VARIABLE generated
                ERROR_VARIABLE error RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "`shellflow plugins --markdown` failed (${status}): ${error}")
endif()
file(READ ${REFERENCE} committed)
if(NOT generated STREQUAL committed)
  message(FATAL_ERROR "${REFERENCE} is stale: a plugin's parameters changed. Regenerate it "
                      "from the build folder with\n  bin/shellflow plugins --markdown > ${REFERENCE}")
endif()
