# The data programs load at run time (core::dataDirectory): the segmentation model, the person
# cut-outs, the sample recording and the configuration files, under share/semantic-mapper beside
# bin/. The build tree gets the same layout as links to the source folders, so build/bin/*
# finds its data exactly as an installed program does; nothing is compiled in from the source.
include(GNUInstallDirs)

set(SMAP_DATA_SUBDIR "${CMAKE_INSTALL_DATADIR}/semantic-mapper")
set(SMAP_BUILD_DATA_DIR "${CMAKE_BINARY_DIR}/${SMAP_DATA_SUBDIR}")
# name in the data folder -> folder in the source tree
set(SMAP_DATA_FOLDERS "models=models" "people=data/people" "rawlogs=rawlogs" "config=config")

file(MAKE_DIRECTORY "${SMAP_BUILD_DATA_DIR}")
foreach(entry IN LISTS SMAP_DATA_FOLDERS)
    string(REPLACE "=" ";" pair "${entry}")
    list(GET pair 0 name)
    list(GET pair 1 source)
    if(NOT IS_SYMLINK "${SMAP_BUILD_DATA_DIR}/${name}")
        file(CREATE_LINK "${PROJECT_SOURCE_DIR}/${source}" "${SMAP_BUILD_DATA_DIR}/${name}"
            SYMBOLIC)
    endif()
    install(DIRECTORY "${PROJECT_SOURCE_DIR}/${source}/"
        DESTINATION "${SMAP_DATA_SUBDIR}/${name}")
endforeach()
