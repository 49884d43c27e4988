# The Debian package (cpack -G DEB), built from the install rules. Runtime dependencies
# of the binaries come from dpkg-shlibdeps; what is only run (lcm-spy's Java side, the
# LCM tools) is recommended.
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
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "liblcm-bin, liblcm-java, libjchart2d-java, default-jre-headless")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_STRIP_FILES ON)
include(CPack)
