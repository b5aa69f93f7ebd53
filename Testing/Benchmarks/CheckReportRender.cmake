# CheckReportRender.cmake: renders RESULTS/report.json into OUT with SCRIPT and requires the
# report.md it writes to equal RESULTS/report.md byte for byte.
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${PYTHON}" "${SCRIPT}" --out "${OUT}" --json "${RESULTS}/report.json"
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "report_render.py failed (${code}):\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${OUT}/report.md" "${RESULTS}/report.md"
  RESULT_VARIABLE differ)
if(NOT differ EQUAL 0)
  message(FATAL_ERROR "${OUT}/report.md differs from ${RESULTS}/report.md: the renderer no longer "
    "reproduces the committed report from its report.json")
endif()
message(STATUS "report.md reproduced from report.json")
