# Fails the build when a code generator "succeeded" without writing its output: idlc and lcm-gen
# both exit 0 when they cannot write to their output directory.
#   cmake -DTOOL=<name> -DFILES=<file>|<file>|... -P check_generated.cmake
string(REPLACE "|" ";" files "${FILES}")
foreach(file IN LISTS files)
  if(NOT EXISTS "${file}")
    message(FATAL_ERROR "${TOOL} exited 0 but did not write ${file}")
  endif()
endforeach()
