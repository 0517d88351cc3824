# Drops ATLAS's libf77blas and libatlas from the link interfaces of Ceres (Debian's config lists
# them after the generic libblas and liblapack) and of SuiteSparse, so that every BLAS symbol of
# CHOLMOD and Ceres binds to libblas.so.3 / liblapack.so.3, i.e. to the system's alternative.
foreach(target Ceres::ceres SuiteSparse::Config SuiteSparse::CHOLMOD)
  if(TARGET ${target})
    get_target_property(libs ${target} INTERFACE_LINK_LIBRARIES)
    if(libs)
      list(FILTER libs EXCLUDE REGEX "lib(f77blas|atlas|cblas)\\.so")
      set_target_properties(${target} PROPERTIES INTERFACE_LINK_LIBRARIES "${libs}")
    endif()
  endif()
endforeach()
