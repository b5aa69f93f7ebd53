# CheckBundle.cmake: a shipped model bundle loads and reproduces its recorded check figures.
# Regenerates the bundle's first CHECK held-out exemplars (seed 1, indices from 1 000 000, the
# bundle's image size and design-space spec), evaluates the bundle on them and compares PSNR and SSIM with
# bundle.json's metrics.check within PSNR_TOL dB and SSIM_TOL. A shipped bundle must also have
# met issue 4's bar on its 1 000 held-out exemplars (recorded in metrics): bar.json beside this
# script, PSNR >= 28 dB, SSIM >= 0.90, invariance >= 0.95.
#   cmake -DDDG=... -DVOLUME=... -DBUNDLE=... -DWORK=... -P CheckBundle.cmake
set(PSNR_TOL 0.1)
set(SSIM_TOL 0.002)
file(READ "${BUNDLE}/bundle.json" bundle)
file(READ "${CMAKE_CURRENT_LIST_DIR}/bar.json" bar)
string(JSON minPsnr GET "${bar}" psnr)
string(JSON minSsim GET "${bar}" ssim)
string(JSON minInvariance GET "${bar}" invariance)
string(JSON size GET "${bundle}" architecture image_size)
string(JSON count GET "${bundle}" metrics check heldout_count)
string(JSON psnr GET "${bundle}" metrics check psnr)
string(JSON ssim GET "${bundle}" metrics check ssim)
string(JSON heldoutCount GET "${bundle}" metrics heldout_count)
string(JSON barPsnr GET "${bundle}" metrics psnr)
string(JSON barSsim GET "${bundle}" metrics ssim)
string(JSON barInvariance GET "${bundle}" metrics invariance)
if(heldoutCount LESS 1000)
  message(FATAL_ERROR "the bundle was evaluated on ${heldoutCount} held-out exemplars, not 1000")
endif()
execute_process(COMMAND awk "BEGIN { exit (${barPsnr} >= ${minPsnr} && ${barSsim} >= ${minSsim} && ${barInvariance} >= ${minInvariance}) ? 0 : 1 }"
  RESULT_VARIABLE meets)
if(NOT meets EQUAL 0)
  message(FATAL_ERROR "the bundle misses the bar: PSNR ${barPsnr} dB, SSIM ${barSsim}, invariance ${barInvariance}")
endif()
# the held-out exemplars of the bundle's own design space (e.g. lit ones, users' pictures)
string(JSON spec GET "${bundle}" spec)
file(WRITE "${WORK}_spec.json" "${spec}")
execute_process(COMMAND "${DDG}" generate --volume "${VOLUME}" --count ${count} --size ${size} --seed 1
    --first-index 1000000 --spec "${WORK}_spec.json" --out "${WORK}" --quiet
  RESULT_VARIABLE code OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "ddg generate failed: ${err}")
endif()
execute_process(COMMAND "${DDG}" eval --model "${BUNDLE}" --data "${WORK}" --count ${count} --json --volume "${VOLUME}"
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "ddg eval failed: ${err}")
endif()
string(JSON gotPsnr GET "${out}" psnr)
string(JSON gotSsim GET "${out}" ssim)
foreach(pair "psnr;${psnr};${gotPsnr};${PSNR_TOL}" "ssim;${ssim};${gotSsim};${SSIM_TOL}")
  list(GET pair 0 name)
  list(GET pair 1 want)
  list(GET pair 2 got)
  list(GET pair 3 tol)
  # CMake has no float arithmetic: awk (in every Debian) checks |got - want| <= tol.
  execute_process(COMMAND awk "BEGIN { d = ${got} - ${want}; if (d < 0) d = -d; exit (d <= ${tol}) ? 0 : 1 }"
    RESULT_VARIABLE within)
  if(NOT within EQUAL 0)
    message(FATAL_ERROR "${name}: recorded ${want}, reproduced ${got} (tolerance ${tol})")
  endif()
  message(STATUS "${name}: recorded ${want}, reproduced ${got}")
endforeach()
