# Writes OUTPUT, a header defining MILLWEAR_COMMIT: the short commit of SOURCE_DIR, with
# "-dirty" if tracked files have uncommitted changes, or "unknown" when SOURCE_DIR is not the
# top of a git checkout (a source archive, or a copy inside another project's repository) or
# git is missing. The file is rewritten only when its text changes, so the build recompiles
# only what includes it, and only then.
#   cmake -DSOURCE_DIR=... -DOUTPUT=.../millwear_commit.hpp -P commit_header.cmake
set(commit "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} rev-parse --show-prefix
                  RESULT_VARIABLE prefix_status OUTPUT_VARIABLE prefix
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} rev-parse --short=7 HEAD
                  RESULT_VARIABLE head_status OUTPUT_VARIABLE head
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(prefix_status EQUAL 0 AND prefix STREQUAL "" AND head_status EQUAL 0 AND NOT head STREQUAL "")
    set(commit "${head}")
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} status --porcelain
                            --untracked-files=no
                    RESULT_VARIABLE status_status OUTPUT_VARIABLE changes ERROR_QUIET)
    if(status_status EQUAL 0 AND NOT changes STREQUAL "")
      string(APPEND commit "-dirty")
    endif()
  endif()
endif()

set(text "// Generated at build time by cmake/commit_header.cmake; do not edit.\n#pragma once\n#define MILLWEAR_COMMIT \"${commit}\"\n")
set(old "")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUTPUT} "${text}")
endif()
