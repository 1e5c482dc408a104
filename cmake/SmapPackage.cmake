# What `cmake --install` and `cpack -G DEB` deliver beyond the programs and the data folder
# (SmapHelpers.cmake installs each library and its headers, SmapData.cmake the data): the CMake
# package an outside project finds with find_package(semantic_mapper CONFIG REQUIRED), the docs,
# and the Debian package's description.
include(CMakePackageConfigHelpers)

set(SMAP_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/semantic_mapper")
install(EXPORT smapTargets NAMESPACE smap:: FILE semantic_mapperTargets.cmake
    DESTINATION "${SMAP_CMAKE_DIR}")
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/semantic_mapperConfig.cmake.in"
    "${PROJECT_BINARY_DIR}/semantic_mapperConfig.cmake"
    INSTALL_DESTINATION "${SMAP_CMAKE_DIR}"
    PATH_VARS SMAP_DATA_SUBDIR)
write_basic_package_version_file("${PROJECT_BINARY_DIR}/semantic_mapperConfigVersion.cmake"
    COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/semantic_mapperConfig.cmake"
    "${PROJECT_BINARY_DIR}/semantic_mapperConfigVersion.cmake"
    DESTINATION "${SMAP_CMAKE_DIR}")

install(FILES "${PROJECT_SOURCE_DIR}/README.md" "${PROJECT_SOURCE_DIR}/LICENSE"
    "${PROJECT_SOURCE_DIR}/THIRD_PARTY_NOTICES.md" DESTINATION "${CMAKE_INSTALL_DOCDIR}")

# The Debian copyright file (machine-readable format): our licence and the shipped model's and
# person cut-outs' (THIRD_PARTY_NOTICES.md), each licence text indented as the format wants.
function(smap_debian_licence_text path out)
    file(READ "${path}" text)
    string(REGEX REPLACE "\n+$" "" text "${text}")
    string(REGEX REPLACE "\n\n" "\n.\n" text "${text}")
    string(REGEX REPLACE "\n" "\n " text "${text}")
    set(${out} " ${text}" PARENT_SCOPE)
endfunction()
smap_debian_licence_text("${PROJECT_SOURCE_DIR}/LICENSE" BSD_TEXT)
smap_debian_licence_text("${PROJECT_SOURCE_DIR}/models/espnetv2-voc/LICENSE.EdgeNets" MIT_TEXT)
configure_file("${PROJECT_SOURCE_DIR}/cmake/copyright.in" "${PROJECT_BINARY_DIR}/copyright" @ONLY)
install(FILES "${PROJECT_BINARY_DIR}/copyright" DESTINATION "${CMAKE_INSTALL_DOCDIR}")
install(DIRECTORY "${PROJECT_SOURCE_DIR}/docs/" DESTINATION "${CMAKE_INSTALL_DOCDIR}")
install(DIRECTORY "${PROJECT_SOURCE_DIR}/examples/" DESTINATION "${CMAKE_INSTALL_DOCDIR}/examples")

# cpack -G DEB (run in the build folder): semantic-mapper_<version>_amd64.deb, installing under
# /usr. Its run-time dependencies are what dpkg-shlibdeps finds the programs and libraries
# linked against; the -dev packages a program built against the CMake package needs are
# suggested (recommended, apt-get would install MRPT's whole development stack with it).
set(CPACK_PACKAGE_NAME "semantic-mapper")
set(CPACK_PACKAGE_VENDOR "semantic-mapper developers")
set(CPACK_PACKAGE_CONTACT "semantic-mapper developers <semantic-mapper@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "3D semantic maps from RGB-D recordings, robust to people walking through the scene")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION "science")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Our own libraries are in the package: dpkg-shlibdeps must look for them there.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS "${PROJECT_BINARY_DIR}/lib")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS
    "libmrpt-dev (>= 1:2.5), libopencv-dev (>= 4.6), libeigen3-dev, cmake, g++")
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION
    "Builds 3D semantic maps (MRPT CMetricMaps: a semantic OctoMap and a labelled point map)\n from RGB-D recordings (MRPT rawlogs, TUM folders) with ORB-feature SLAM whose\n features are cleaned of moving people, CNN segmentation of keyframes and dynamic\n object removal. Includes the programs, the libraries with their headers and CMake\n package (find_package(semantic_mapper)), the segmentation model, configuration\n and documentation.")
include(CPack)
