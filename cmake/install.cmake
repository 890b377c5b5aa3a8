# What `cmake --install` puts under the prefix, and the Debian package made from it by CPack:
#   bin/millwear
#   share/millwear/{plots,scenarios,profiles,validation}
#                                               the scenarios and the validation examples
#                                               name ../profiles/, so they resolve there as
#                                               in the repository
#   share/doc/millwear/{README.md,docs/}        README's links to docs/ resolve there
#   share/millwear/docs, share/doc/millwear/{plots,validation}
#                                               relative links, so that the Markdown files'
#                                               links resolve as in the repository
#   share/man/man1/millwear.1.gz                from `millwear --help` by help2man
#   share/bash-completion/completions/millwear
# The layout is fixed (bin/ beside share/): the program finds its figure scripts at
# EXEDIR/../share/millwear/plots (src/plots/plots.cpp). Tests and benchmarks install nothing.
install(TARGETS millwear RUNTIME DESTINATION bin)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/plots ${PROJECT_SOURCE_DIR}/scenarios
                  ${PROJECT_SOURCE_DIR}/profiles ${PROJECT_SOURCE_DIR}/validation
        DESTINATION share/millwear)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION share/doc/millwear)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs DESTINATION share/doc/millwear)
# The READMEs and docs/ link each other as in the repository (docs/ to ../validation/,
# plots/ and validation/ to ../docs/): relative links between the two folders keep every
# link whole.
install(CODE [[
  set(share "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}/share")
  file(CREATE_LINK ../doc/millwear/docs "${share}/millwear/docs" SYMBOLIC)
  file(CREATE_LINK ../../millwear/plots "${share}/doc/millwear/plots" SYMBOLIC)
  file(CREATE_LINK ../../millwear/validation "${share}/doc/millwear/validation" SYMBOLIC)
]])
install(FILES ${PROJECT_SOURCE_DIR}/packaging/millwear.bash
        DESTINATION share/bash-completion/completions RENAME millwear)

if(MILLWEAR_BUILD_MAN)
  find_program(HELP2MAN_EXECUTABLE help2man REQUIRED)
  find_program(GZIP_EXECUTABLE gzip REQUIRED)
  set(man_dir ${CMAKE_CURRENT_BINARY_DIR}/man)
  add_custom_command(
    OUTPUT ${man_dir}/millwear.1.gz
    COMMAND ${CMAKE_COMMAND} -E make_directory ${man_dir}
    COMMAND ${HELP2MAN_EXECUTABLE} --no-info --section=1
            "--name=lifter wear in grinding mills by DEM and Archard's law"
            --include=${PROJECT_SOURCE_DIR}/packaging/millwear.h2m
            --output=${man_dir}/millwear.1 $<TARGET_FILE:millwear>
    COMMAND ${GZIP_EXECUTABLE} -n -9 -f ${man_dir}/millwear.1
    DEPENDS millwear ${PROJECT_SOURCE_DIR}/packaging/millwear.h2m
    COMMENT "Generating the man page with help2man"
    VERBATIM)
  add_custom_target(millwear_man ALL DEPENDS ${man_dir}/millwear.1.gz)
  install(FILES ${man_dir}/millwear.1.gz DESTINATION share/man/man1)
endif()

# CPack, only when millwear is the project being built (a parent project packages itself).
if(MILLWEAR_TOP_LEVEL)
  set(MILLWEAR_PACKAGE_MAINTAINER "millwear maintainers <maintainers@millwear.invalid>"
      CACHE STRING "Maintainer field of the Debian package")
  set(CPACK_GENERATOR DEB)
  set(CPACK_PACKAGE_NAME millwear)
  set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
  set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
      "lifter wear in grinding mills by DEM and Archard's law (2D slice)")
  string(CONCAT CPACK_PACKAGE_DESCRIPTION
    "millwear predicts how the lifter bars of a grinding mill (SAG, AG, ball) wear and what\n"
    "that wear does to the mill. It simulates a 2D cross-section: the charge of rocks and\n"
    "balls on a contact solver, the liner wearing edge by edge by Archard's law. Outputs are\n"
    "worn profiles stage by stage, lifter area, height and life, power draw, collision\n"
    "energy and energy utilisation, compared between lifter designs, with figures drawn by\n"
    "gnuplot.")
  set(CPACK_PACKAGE_CONTACT "${MILLWEAR_PACKAGE_MAINTAINER}")
  set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${MILLWEAR_PACKAGE_MAINTAINER}")
  set(CPACK_DEBIAN_PACKAGE_SECTION science)
  set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
  set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
  # The shared libraries (Boost, Box2D, libstdc++, ...) come from dpkg-shlibdeps; gnuplot is
  # run as a program for the figures, so no library names it.
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "gnuplot-nox | gnuplot")
  set(CPACK_STRIP_FILES ON)
  include(CPack)
endif()
