# All third-party packages, found once. Every one comes from Debian 12 (deps/debian-packages.txt).
find_package(glm REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(fmt REQUIRED)
find_package(assimp REQUIRED)
find_package(pugixml REQUIRED)  # Mitsuba 3 XML scenes (common/formats/mitsuba/scene_mitsuba.cpp)
find_package(ZLIB REQUIRED)  # Mitsuba's serialized meshes (common/formats/mitsuba/mitsuba_serialized.cpp)
find_package(TBB REQUIRED)
find_package(embree 3 REQUIRED)
find_package(OpenImageIO REQUIRED)  # bench/'s image comparison tool only (any format a user's reference is in)
find_package(OpenEXR 3 CONFIG REQUIRED)  # the renderer's images (render/output/image_io.h)
find_package(PNG REQUIRED)
find_package(JPEG REQUIRED)  # with libpng: imported assets' texture images (common/materials/texture_image.h)
find_package(Freetype REQUIRED)  # the false-colour legend's text
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)
find_package(glfw3 3.3 REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(OSMESA REQUIRED IMPORTED_TARGET osmesa)
find_package(Threads REQUIRED)

# Debian's OpenImageIO target names /usr/include/opencv4, which need not exist: drop it.
foreach(prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
  get_target_property(_dirs OpenImageIO::OpenImageIO ${prop})
  if(_dirs)
    list(FILTER _dirs EXCLUDE REGEX "opencv4")
    set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${prop} "${_dirs}")
  endif()
endforeach()

# Embree's imported target does not bring TBB along.
add_library(firstshot_embree INTERFACE)
target_link_libraries(firstshot_embree INTERFACE embree TBB::tbb)

# OpenGL 4.5 core loader, generated at build time by Debian's python3-glad from its bundled XML
# (--reproducible: no download).
find_program(SYSTEM_PYTHON3 NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH REQUIRED)
set(GLAD_DIR ${CMAKE_BINARY_DIR}/glad)
add_custom_command(
  OUTPUT ${GLAD_DIR}/src/gl.c ${GLAD_DIR}/include/glad/gl.h
  COMMAND ${SYSTEM_PYTHON3} -m glad --quiet --reproducible --api gl:core=4.5 "--extensions="
          --out-path ${GLAD_DIR} c
  COMMENT "Generating the OpenGL 4.5 core loader with glad")
add_library(firstshot_glad STATIC ${GLAD_DIR}/src/gl.c)
target_include_directories(firstshot_glad SYSTEM PUBLIC ${GLAD_DIR}/include)
set_target_properties(firstshot_glad PROPERTIES POSITION_INDEPENDENT_CODE ON)

find_package(GTest REQUIRED)
find_package(benchmark REQUIRED)
