# ctest driver: what libpydrill exports. Run with NM (nm), LIBRARY (libpydrill.so, or empty
# for a static build) and PROBE (a user's shared library linked with pydrill::pydrill).
#  - A shared libpydrill exports its public API (PYDRILL_API in include/pydrill) and nothing
#    of its internals: no pydrill::detail, no banded solver, no Eigen instantiation.
#  - A user's shared library that links pydrill exports nothing of pydrill's (a static
#    libpydrill's objects are hidden; a shared one is only referenced).
foreach(var NM PROBE)
  if(NOT ${var})
    message(FATAL_ERROR "${var} not set")
  endif()
endforeach()

# Demangled names of the defined dynamic symbols of a shared object.
function(exported file out)
  execute_process(COMMAND ${NM} -D --defined-only -C ${file}
                  OUTPUT_VARIABLE text RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(rc)
    message(FATAL_ERROR "${NM} -D ${file} failed: ${err}")
  endif()
  string(REPLACE ";" "\\;" text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  set(${out} ${lines} PARENT_SCOPE)
endfunction()

# What must never be exported: pydrill's internals and the instantiations of Eigen, which a
# program with its own Eigen would otherwise bind to ours.
set(internal "pydrill::detail|pydrill::BandLU|pydrill::\\(anonymous|Eigen::")

if(LIBRARY)
  exported(${LIBRARY} symbols)
  set(public 0)
  set(leaked)
  foreach(line ${symbols})
    if(line MATCHES "${internal}")
      list(APPEND leaked "${line}")
    elseif(line MATCHES " pydrill::")
      math(EXPR public "${public} + 1")
    endif()
  endforeach()
  list(LENGTH symbols total)
  message(STATUS "${LIBRARY}: ${total} symbols exported, ${public} of them pydrill's public API")
  if(leaked)
    string(REPLACE ";" "\n  " leaked "${leaked}")
    message(FATAL_ERROR "internals exported:\n  ${leaked}")
  endif()
  foreach(api "pydrill::simulate\\(" "pydrill::critical_deltas\\(" "pydrill::Params::validate\\(\\) const"
              "pydrill::Chain::rhs\\(" "typeinfo for pydrill::SolverError"
              "typeinfo for pydrill::StabilityInterrupted" "pydrill::regime_name\\(")
    string(REGEX MATCH "[^;]*${api}[^;]*" found "${symbols}")
    if(NOT found)
      message(FATAL_ERROR "${LIBRARY} does not export ${api}")
    endif()
  endforeach()
endif()

exported(${PROBE} symbols)
set(leaked)
foreach(line ${symbols})
  if(line MATCHES "pydrill::|${internal}")
    list(APPEND leaked "${line}")
  endif()
endforeach()
if(leaked)
  string(REPLACE ";" "\n  " leaked "${leaked}")
  message(FATAL_ERROR "a user's library that links pydrill exports pydrill's symbols:\n  ${leaked}")
endif()
message(STATUS "${PROBE}: exports nothing of pydrill's")
