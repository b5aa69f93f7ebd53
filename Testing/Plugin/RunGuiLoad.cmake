# RunGuiLoad.cmake: starts the ParaView GUI under xvfb with the plugin, runs GuiLoadCheck.py and
# checks the marker it writes.
file(REMOVE "${MARKER}")
set(ENV{DDG_GUI_MARKER} "${MARKER}")
set(ENV{DDG_DATA_DIR} "${DATA}")
string(REPLACE "|" ";" XVFB "${XVFB}")
execute_process(
  COMMAND ${XVFB} paraview --dr "--plugin-search-paths=${PLUGIN_DIR}" --plugins=DesignGallery
    "--script=${SCRIPT}" "--test-script=${EVENTS}" --exit
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 240)
if(NOT EXISTS "${MARKER}")
  message(FATAL_ERROR "the GUI did not run DDG Volume Render (exit ${code})\n${out}\n${err}")
endif()
file(READ "${MARKER}" text)
message(STATUS "${text}")
