# The Debian package (cpack -G DEB), built from the install rules. Runtime dependencies
# of the binaries come from dpkg-shlibdeps; what is only run (lcm-spy's Java side, the
# LCM tools) is recommended.
#
# The unit's ExecStart and the configuration's place are absolute paths fixed at configure
# time, so a package is only right when configured for the prefix it installs to.
if(NOT CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  message(STATUS "ccdlane: CMAKE_INSTALL_PREFIX is ${CMAKE_INSTALL_PREFIX}; configure with "
                 "-DCMAKE_INSTALL_PREFIX=/usr before `cpack -G DEB`")
endif()
set(CPACK_PACKAGE_NAME ccdlane)
set(CPACK_PACKAGE_VENDOR "ccdlane")
set(CPACK_PACKAGE_CONTACT "ccdlane maintainers <ccdlane-maintainers@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "Lane attitude and lane-line estimation from one camera, with a 3DM-GX1 gyro, publishing over LCM")
set(CPACK_PACKAGE_DESCRIPTION
  "ccdlaned captures frames (V4L2 or GenICam/Aravis), reads a MicroStrain 3DM-GX1 gyro, solves the camera
attitude and the lane lines by least squares on every frame and publishes lane messages over LCM for a
lane departure warning consumer. ccdlane is the command-line tool (solve, replay, record, monitor, spy).")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# lcm-spy is a Swing program: a JRE with AWT (not -headless) runs `ccdlane spy`;
# `ccdlane report` draws with Debian's matplotlib.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "liblcm-bin, liblcm-java, libjchart2d-java, default-jre, python3-matplotlib")
# The configuration is the user's: dpkg keeps their edits on upgrade and asks before
# replacing a changed file; `apt-get purge` removes it.
set(ccdlane_conffiles "${CMAKE_BINARY_DIR}/debian/conffiles")
file(WRITE "${ccdlane_conffiles}" "${CCDLANE_CONFIG_INSTALL_DIR}/ccdlane.toml\n")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA "${ccdlane_conffiles}")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_STRIP_FILES ON)
include(CPack)
