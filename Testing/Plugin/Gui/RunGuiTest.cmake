# RunGuiTest.cmake: one Design Gallery GUI test: ParaView under Xvfb with the plugin, the scene of
# GuiSetup.py (CASE), the XML events EVENTS (panel clicks, image comparisons against baselines,
# property checks); fails on any failed event or crash, then checks the colour map the panel
# wrote against EXPECTED (ddg's preset for the same design) with CheckGuiRecord.py (SEQUENCE).
string(REPLACE "|" ";" XVFB "${XVFB}")
set(ENV{DDG_GUI_CASE} "${CASE}")
set(ENV{DDG_DATA_DIR} "${DATA}")
set(ENV{DDG_TEST_DATA} "${TESTDATA}")
set(ENV{DDG_GUI_RECORD} "${OUT}/record.txt")
file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
if(EXPECT_CMD)
  string(REPLACE "|" ";" EXPECT_CMD "${EXPECT_CMD}")
  execute_process(COMMAND ${EXPECT_CMD} RESULT_VARIABLE code OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "the expected preset could not be made: ${err}")
  endif()
endif()
execute_process(
  COMMAND ${XVFB} paraview --dr "--plugin-search-paths=${PLUGIN_DIR}" --plugins=DesignGallery
    "--script=${SCRIPT}" "--test-script=${EVENTS}" "--test-directory=${OUT}" --exit
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 280)
set(log "${out}\n${err}")
file(WRITE "${OUT}/paraview.log" "${log}")
if(log MATCHES "FAILED|SIGSEGV|SIGABRT|Couldn't find object|Unhandled error" OR NOT code EQUAL 0)
  message(FATAL_ERROR "the GUI test failed (exit ${code}):\n${log}")
endif()
message(STATUS "GUI events passed (images within their thresholds)")
if(SEQUENCE)
  execute_process(COMMAND /usr/bin/python3 "${CHECK}" "${OUT}/record.txt" "${EXPECTED}" "${SEQUENCE}"
    RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${out}")
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${err}")
  endif()
endif()
