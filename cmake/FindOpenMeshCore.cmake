# FindOpenMeshCore: the core library of OpenMesh (Debian: libopenmesh-dev),
# found by path.
#
#   OpenMesh::Core   imported target
#   OpenMeshCore_FOUND, OPENMESH_INCLUDE_DIR, OPENMESH_CORE_LIB
find_path(OPENMESH_INCLUDE_DIR OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh)
find_library(OPENMESH_CORE_LIB NAMES OpenMeshCore)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenMeshCore REQUIRED_VARS OPENMESH_CORE_LIB OPENMESH_INCLUDE_DIR)
mark_as_advanced(OPENMESH_INCLUDE_DIR OPENMESH_CORE_LIB)

if(OpenMeshCore_FOUND AND NOT TARGET OpenMesh::Core)
  add_library(OpenMesh::Core UNKNOWN IMPORTED)
  set_target_properties(OpenMesh::Core PROPERTIES
    IMPORTED_LOCATION "${OPENMESH_CORE_LIB}"
    INTERFACE_INCLUDE_DIRECTORIES "${OPENMESH_INCLUDE_DIR}")
endif()
