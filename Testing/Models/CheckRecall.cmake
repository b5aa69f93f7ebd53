# CheckRecall.cmake: query recall of a shipped bundle: 200 held-out designs (indices from
# 2 000 000, never in training or the outline) join its outline; each is queried with its own
# image and with its image from another view. The own-image query must find it among the 5
# nearest in >= 90 % of the cases (issue 5's bar); the other view is printed. A bundle with a
# query key (query_key.json) must find more designs from the other view by it than by the
# latents as they are (--no-key), and at least 50 % of them (issue 20's bar); `ddg query` then
# lists a picture's neighbours by key distance (by latent distance with --no-key).
#   cmake -DDDG=... -DVOLUME=... -DBUNDLE=... -DWORK=... -P CheckRecall.cmake
file(READ "${BUNDLE}/bundle.json" bundle)
string(JSON size GET "${bundle}" architecture image_size)
execute_process(COMMAND ${DDG} generate --volume ${VOLUME} --count 200 --size ${size} --seed 1
    --first-index 2000000 --out ${WORK} --quiet RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "ddg generate failed: ${err}")
endif()
# ddg recall with the extra arguments given: the own-image and other-view percentages into `own`, `other`
function(recall own other)
  execute_process(COMMAND ${DDG} recall --model ${BUNDLE} --data ${WORK} --count 200 --k 5 ${ARGN}
    RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "ddg recall ${ARGN} failed: ${err}")
  endif()
  message(STATUS "${out}")
  if(NOT out MATCHES "own image ([0-9.]+) %, other view ([0-9.]+) %")
    message(FATAL_ERROR "unexpected output of ddg recall ${ARGN}: ${out}")
  endif()
  set(${own} ${CMAKE_MATCH_1} PARENT_SCOPE)
  set(${other} ${CMAKE_MATCH_2} PARENT_SCOPE)
endfunction()
recall(own other)
if(own LESS 90)
  message(FATAL_ERROR "the query of a design's own image found it among the 5 nearest in "
    "${own} % of 200 held-out cases (bar: 90 %)")
endif()
if(EXISTS "${BUNDLE}/query_key.json")
  recall(own_latents other_latents --no-key)
  if(NOT other GREATER other_latents)
    message(FATAL_ERROR "the query key found ${other} % of the designs from another view, "
      "the latents as they are ${other_latents} %: the key should find more")
  endif()
  if(other LESS 50)
    message(FATAL_ERROR "the query key found ${other} % of the designs from another view "
      "among the 5 nearest (bar: 50 %)")
  endif()
  # ddg query finds a picture's nearest designs by the key, and says so (--no-key: the latents)
  get_filename_component(name "${VOLUME}" NAME_WE)
  get_filename_component(data "${VOLUME}" DIRECTORY)
  get_filename_component(data "${data}" DIRECTORY)
  file(GLOB pictures "${data}/Screenshots/${name}_*.png")
  list(GET pictures 0 picture)
  foreach(space key latent)
    set(flag "")
    if(space STREQUAL "latent")
      set(flag --no-key)
    endif()
    execute_process(COMMAND ${DDG} query --model ${BUNDLE} --volume ${VOLUME} --image ${picture}
      --view ${data}/Views/${name}_oblique.json ${flag}
      RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT code EQUAL 0 OR NOT out MATCHES "neighbour 1: design row [0-9]+ .index [0-9]+., ${space} distance")
      message(FATAL_ERROR "ddg query ${flag} should list its neighbours by ${space} distance:\n${out}${err}")
    endif()
  endforeach()
endif()
