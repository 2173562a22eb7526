# Stability sweep, fast cases (docs/stability.md): te safety 0.5-1.5, no damping, yarn modulus,
# bending, 3 x 3 and 100 x 100 grids, loads past breaking, both integrators, 1 and 2 ranks.
# Every run must balance to the exact answer or stop with a clear message; none may end with
# NaN/Inf in its outputs, crash, hang or report a wrong state as converged; and each ends as the script's FAST_EXPECT
# says (balanced right, stopped clearly, or flagged unbalanced). Under a minute.
# Included from tests/CMakeLists.txt, which defines MPIEXEC_ENV:
#   include(${CMAKE_CURRENT_SOURCE_DIR}/stability.cmake)
add_test(NAME stability_sweep_fast
         COMMAND ${PROJECT_SOURCE_DIR}/scripts/stability_sweep.sh -fast --fabric $<TARGET_FILE:fabric>)
set_tests_properties(stability_sweep_fast PROPERTIES LABELS stability TIMEOUT 300 ENVIRONMENT "${MPIEXEC_ENV}")
