# Every third-party package comes from Debian 12 (scripts/install-deps.sh).

# Trap 1 (docs/building.md): FindOpenVDB.cmake ships in libopenvdb-dev, off CMake's default path.
find_path(VDBAPPEAR_OPENVDB_MODULE_DIR FindOpenVDB.cmake
  PATHS /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB /usr/lib/cmake/OpenVDB
        /usr/local/lib/cmake/OpenVDB /usr/local/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB
  NO_DEFAULT_PATH)
if(NOT VDBAPPEAR_OPENVDB_MODULE_DIR)
  message(FATAL_ERROR "FindOpenVDB.cmake not found: run scripts/install-deps.sh (libopenvdb-dev)")
endif()
list(APPEND CMAKE_MODULE_PATH "${VDBAPPEAR_OPENVDB_MODULE_DIR}")

# Trap 2: FindOpenVDB asks for Boost iostreams (libboost-iostreams-dev).
find_package(OpenVDB REQUIRED)
find_package(TBB REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(fmt REQUIRED)
find_package(Boost 1.74 REQUIRED)   # header-only parts: math (chi-square, quadrature) in tests
find_package(GTest REQUIRED)
# Quadratic programming for the altered phase functions (similarity paper, Eq. 31). ALGLIB's config
# sets ALGLIB_LIB and ALGLIB_INCLUDE_DIRS (headers in /usr/include/libalglib) instead of a target.
find_package(ALGLIB REQUIRED)
# OpenEXR files through OpenEXR itself (target OpenEXR::OpenEXR; image/exr_file.h).
find_package(OpenEXR 3 REQUIRED CONFIG)
# OpenImageIO (other image formats, a module loaded on demand) through pkg-config: its CMake config names a missing OpenCV include folder (build note 3).
find_package(PkgConfig REQUIRED)
pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)
# Surfaces: Embree 3 (target `embree`) and meshes through Assimp (OBJ, PLY, ...).
find_package(embree 3 REQUIRED)
find_package(assimp REQUIRED)
# Content hashes (XXH3) for the cache of reference images (optimize/reference_cache.h).
pkg_check_modules(XXHASH REQUIRED IMPORTED_TARGET libxxhash)
# The checked chunk readers that replace OpenVDB 10's (io/vdb_chunk_guard.cpp) decompress with the
# same codecs OpenVDB uses: blosc (libblosc-dev) and zlib (zlib1g-dev).
pkg_check_modules(BLOSC REQUIRED IMPORTED_TARGET blosc)
find_package(ZLIB REQUIRED)
# Optional: MPI (Open MPI: libopenmpi-dev) for vdb_render and vdb_optimize_weights on several
# processes (cluster/process_group.h, docs/scaling.md). Without it every tool is one process.
option(VDBAPPEAR_MPI "split renders over MPI ranks when MPI is found" ON)
if(VDBAPPEAR_MPI)
  find_package(MPI COMPONENTS CXX)
endif()
set(VDBAPPEAR_WITH_MPI ${MPI_CXX_FOUND})
