# verification, stability and MPI tests (C++ executables linked to the core)
granhydro_test_executable(test_riemann test_riemann.cc)
add_test(NAME verify.riemann COMMAND test_riemann)
set_tests_properties(verify.riemann PROPERTIES LABELS verify TIMEOUT 600)

granhydro_test_executable(test_order test_order.cc)
add_test(NAME verify.order_1d COMMAND test_order 1d)
add_test(NAME verify.order_2d COMMAND test_order 2d)
add_test(NAME verify.order_3d COMMAND ${DEAL_II_MPIEXEC} -n 2 $<TARGET_FILE:test_order> 3d)
set_tests_properties(verify.order_1d verify.order_2d PROPERTIES LABELS verify TIMEOUT 900)
set_tests_properties(verify.order_3d PROPERTIES LABELS "verify;mpi" TIMEOUT 900 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)

granhydro_test_executable(test_conservation test_conservation.cc)
add_test(NAME verify.conservation COMMAND test_conservation)
set_tests_properties(verify.conservation PROPERTIES LABELS verify TIMEOUT 600)

granhydro_test_executable(test_mpi_equivalence test_mpi_equivalence.cc)
add_test(NAME mpi.equivalence_2ranks COMMAND ${DEAL_II_MPIEXEC} -n 2 $<TARGET_FILE:test_mpi_equivalence>)
add_test(NAME mpi.equivalence_3ranks COMMAND ${DEAL_II_MPIEXEC} -n 3 --oversubscribe $<TARGET_FILE:test_mpi_equivalence>)
set_tests_properties(mpi.equivalence_2ranks mpi.equivalence_3ranks PROPERTIES LABELS mpi TIMEOUT 600 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
# 4 and 8 ranks (oversubscribed here): the 3D cases only, the blast bit for bit
foreach(n 4 8)
  add_test(NAME mpi.equivalence_3d_${n}ranks COMMAND ${DEAL_II_MPIEXEC} -n ${n} --oversubscribe $<TARGET_FILE:test_mpi_equivalence> 3d)
  set_tests_properties(mpi.equivalence_3d_${n}ranks PROPERTIES LABELS mpi TIMEOUT 900 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
endforeach()

granhydro_test_executable(test_haff test_haff.cc)
add_test(NAME verify.haff COMMAND test_haff)
set_tests_properties(verify.haff PROPERTIES LABELS verify TIMEOUT 600)

granhydro_test_executable(test_hydrostatic test_hydrostatic.cc)
add_test(NAME verify.hydrostatic_column COMMAND test_hydrostatic)
set_tests_properties(verify.hydrostatic_column PROPERTIES LABELS "verify;stability" TIMEOUT 600)

granhydro_test_executable(test_diffusion_step test_diffusion_step.cc)
add_test(NAME verify.diffusion_step COMMAND test_diffusion_step)
set_tests_properties(verify.diffusion_step PROPERTIES LABELS verify TIMEOUT 900)

add_test(NAME verify.couette COMMAND test_couette)
set_tests_properties(verify.couette PROPERTIES LABELS verify TIMEOUT 600)

granhydro_test_executable(test_effects test_effects.cc)
add_test(NAME verify.effects COMMAND test_effects)
set_tests_properties(verify.effects PROPERTIES LABELS verify TIMEOUT 300)

granhydro_test_executable(test_column_1d3d test_column_1d3d.cc)
add_test(NAME verify.column_1d_vs_3d COMMAND test_column_1d3d ${CMAKE_SOURCE_DIR}/parameters)
set_tests_properties(verify.column_1d_vs_3d PROPERTIES LABELS verify TIMEOUT 600)

granhydro_test_executable(test_energy_output test_energy_output.cc)
add_test(NAME verify.energy_output COMMAND test_energy_output ${CMAKE_SOURCE_DIR}/parameters)
set_tests_properties(verify.energy_output PROPERTIES LABELS verify TIMEOUT 300)

granhydro_test_executable(test_walls test_walls.cc)
add_test(NAME verify.walls COMMAND test_walls)
set_tests_properties(verify.walls PROPERTIES LABELS verify TIMEOUT 300)
granhydro_test_executable(test_couette test_couette.cc)

granhydro_test_executable(test_vibration test_vibration.cc)
add_test(NAME verify.vibration COMMAND test_vibration)
set_tests_properties(verify.vibration PROPERTIES LABELS verify TIMEOUT 300)

# checkpoint/restart: a run killed with SIGKILL mid-way and restarted from its last
# checkpoint ends bitwise in the state of the uninterrupted run (1 rank and 2 ranks)
add_test(NAME verify.restart_after_kill
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/restart_after_kill.sh $<TARGET_FILE:granhydro>
          ${CMAKE_CURRENT_SOURCE_DIR}/data/restart_granular_2d.prm ${CMAKE_CURRENT_BINARY_DIR}/restart_1rank)
add_test(NAME mpi.restart_after_kill_2ranks
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/restart_after_kill.sh $<TARGET_FILE:granhydro>
          ${CMAKE_CURRENT_SOURCE_DIR}/data/restart_granular_2d.prm ${CMAKE_CURRENT_BINARY_DIR}/restart_2ranks
          ${DEAL_II_MPIEXEC} -n 2)
set_tests_properties(verify.restart_after_kill PROPERTIES LABELS verify TIMEOUT 300)
set_tests_properties(mpi.restart_after_kill_2ranks PROPERTIES LABELS mpi TIMEOUT 300 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
# the run summary does not depend on the partition: a 2D granular gas with all effects on 1,
# 2, 3 and 5 ranks (oversubscribed) gives byte-identical summaries apart from the named
# machine and partition entries (times, memory, rank count; tests/summary_ranks.sh)
add_test(NAME mpi.summary_ranks
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/summary_ranks.sh $<TARGET_FILE:granhydro>
          ${CMAKE_CURRENT_SOURCE_DIR}/data/summary_granular_2d.prm ${CMAKE_CURRENT_BINARY_DIR}/summary_ranks
          ${DEAL_II_MPIEXEC} 1 2 3 5)
set_tests_properties(mpi.summary_ranks PROPERTIES LABELS mpi TIMEOUT 300 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
# meshes from files (tests/test_mesh_files.cc): a box read from gmsh/ucd files is bitwise the
# generated box (1 and 2 ranks); the silo closed conserves mass; silo-ci discharges
granhydro_test_executable(test_mesh_files test_mesh_files.cc)
add_test(NAME verify.mesh_file_box COMMAND test_mesh_files box ${CMAKE_CURRENT_SOURCE_DIR}/data)
set_tests_properties(verify.mesh_file_box PROPERTIES LABELS verify TIMEOUT 300)
add_test(NAME mpi.mesh_file_box_2ranks COMMAND ${DEAL_II_MPIEXEC} -n 2 $<TARGET_FILE:test_mesh_files> box ${CMAKE_CURRENT_SOURCE_DIR}/data)
set_tests_properties(mpi.mesh_file_box_2ranks PROPERTIES LABELS "verify;mpi" TIMEOUT 300 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
add_test(NAME stability.silo_closed COMMAND test_mesh_files closed ${CMAKE_SOURCE_DIR}/parameters/silo-ci.prm)
set_tests_properties(stability.silo_closed PROPERTIES LABELS stability TIMEOUT 300)
add_test(NAME mpi.silo_closed_2ranks COMMAND ${DEAL_II_MPIEXEC} -n 2 $<TARGET_FILE:test_mesh_files> closed ${CMAKE_SOURCE_DIR}/parameters/silo-ci.prm)
set_tests_properties(mpi.silo_closed_2ranks PROPERTIES LABELS "stability;mpi" TIMEOUT 300 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
add_test(NAME stability.scene_silo-ci COMMAND test_mesh_files discharge ${CMAKE_SOURCE_DIR}/parameters/silo-ci.prm)
set_tests_properties(stability.scene_silo-ci PROPERTIES LABELS stability TIMEOUT 600)
# adaptive octree refinement (tests/test_amr.cc): conservation with refinement and coarsening
# every 5 steps for 500 steps (1 and 2 ranks); 1 rank vs 2 ranks with AMR; restart with AMR
granhydro_test_executable(test_amr test_amr.cc)
# test_amr slot-grid unit-tests SlotGrid, an internal header of the patch (not installed)
target_include_directories(test_amr PRIVATE ${CMAKE_SOURCE_DIR}/source/mesh)
add_test(NAME verify.amr_conservation COMMAND test_amr conservation)
set_tests_properties(verify.amr_conservation PROPERTIES LABELS verify TIMEOUT 600)
add_test(NAME mpi.amr_conservation_2ranks COMMAND ${DEAL_II_MPIEXEC} -n 2 $<TARGET_FILE:test_amr> conservation)
set_tests_properties(mpi.amr_conservation_2ranks PROPERTIES LABELS mpi TIMEOUT 600 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
add_test(NAME verify.amr_walls_3d COMMAND test_amr walls-3d)
set_tests_properties(verify.amr_walls_3d PROPERTIES LABELS verify TIMEOUT 300)
add_test(NAME mpi.amr_walls_3d_2ranks COMMAND ${DEAL_II_MPIEXEC} -n 2 $<TARGET_FILE:test_amr> walls-3d)
set_tests_properties(mpi.amr_walls_3d_2ranks PROPERTIES LABELS mpi TIMEOUT 300 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
add_test(NAME mpi.amr_open_2d_3ranks COMMAND ${DEAL_II_MPIEXEC} -n 3 --oversubscribe $<TARGET_FILE:test_amr> mpi-open-2d)
set_tests_properties(mpi.amr_open_2d_3ranks PROPERTIES LABELS mpi TIMEOUT 300 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
add_test(NAME verify.amr_slot_grid COMMAND test_amr slot-grid)
set_tests_properties(verify.amr_slot_grid PROPERTIES LABELS verify TIMEOUT 60)
add_test(NAME verify.amr_balance_skip COMMAND test_amr balance)
set_tests_properties(verify.amr_balance_skip PROPERTIES LABELS verify TIMEOUT 120)
add_test(NAME mpi.amr_balance_skip_3ranks COMMAND ${DEAL_II_MPIEXEC} -n 3 --oversubscribe $<TARGET_FILE:test_amr> balance)
set_tests_properties(mpi.amr_balance_skip_3ranks PROPERTIES LABELS mpi TIMEOUT 120 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
add_test(NAME verify.amr_dealii_sync COMMAND test_amr dealii-sync)
set_tests_properties(verify.amr_dealii_sync PROPERTIES LABELS verify TIMEOUT 300)
add_test(NAME mpi.amr_dealii_sync_2ranks COMMAND ${DEAL_II_MPIEXEC} -n 2 $<TARGET_FILE:test_amr> dealii-sync)
set_tests_properties(mpi.amr_dealii_sync_2ranks PROPERTIES LABELS mpi TIMEOUT 300 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
add_test(NAME mpi.amr_equivalence_2ranks COMMAND ${DEAL_II_MPIEXEC} -n 2 $<TARGET_FILE:test_amr> mpi)
set_tests_properties(mpi.amr_equivalence_2ranks PROPERTIES LABELS mpi TIMEOUT 600 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
foreach(n 4 8)
  add_test(NAME mpi.amr_equivalence_3d_${n}ranks COMMAND ${DEAL_II_MPIEXEC} -n ${n} --oversubscribe $<TARGET_FILE:test_amr> mpi-3d)
  set_tests_properties(mpi.amr_equivalence_3d_${n}ranks PROPERTIES LABELS mpi TIMEOUT 900 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
endforeach()
add_test(NAME verify.amr_restart_after_kill
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/restart_after_kill.sh $<TARGET_FILE:granhydro>
          ${CMAKE_CURRENT_SOURCE_DIR}/data/restart_amr_2d.prm ${CMAKE_CURRENT_BINARY_DIR}/restart_amr_1rank)
add_test(NAME mpi.amr_restart_after_kill_2ranks
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/restart_after_kill.sh $<TARGET_FILE:granhydro>
          ${CMAKE_CURRENT_SOURCE_DIR}/data/restart_amr_2d.prm ${CMAKE_CURRENT_BINARY_DIR}/restart_amr_2ranks
          ${DEAL_II_MPIEXEC} -n 2)
set_tests_properties(verify.amr_restart_after_kill PROPERTIES LABELS verify TIMEOUT 300)
set_tests_properties(mpi.amr_restart_after_kill_2ranks PROPERTIES LABELS mpi TIMEOUT 300 ENVIRONMENT "${MPIEXEC_ENV}" PROCESSORS 2)
# the uniform 256^2 reference (3/4 of the test's time) from a golden file, regenerated by
# build/tests/test_amr sod 2 --write-uniform-reference=tests/golden/amr_sod_diagonal_2d_uniform.csv
# (after a change of the uniform solution; the errors are deterministic to round-off)
add_test(NAME verify.amr_sod_diagonal_2d COMMAND test_amr sod 2
  --uniform-reference=${CMAKE_CURRENT_SOURCE_DIR}/golden/amr_sod_diagonal_2d_uniform.csv)
set_tests_properties(verify.amr_sod_diagonal_2d PROPERTIES LABELS verify TIMEOUT 600)

# ---- the dense closure in the solver (tests/test_dense_closure.cc): heat flux along the
# true temperature gradient, frictional work dissipated, a settled column that packs like grains
granhydro_test_executable(test_dense_closure test_dense_closure.cc)
add_test(NAME unit.dense_closure_uniform_temperature COMMAND test_dense_closure uniform_temperature)
set_tests_properties(unit.dense_closure_uniform_temperature PROPERTIES LABELS unit TIMEOUT 120)
add_test(NAME verify.frictional_dissipation_shear COMMAND test_dense_closure frictional_shear)
set_tests_properties(verify.frictional_dissipation_shear PROPERTIES LABELS verify TIMEOUT 300)
add_test(NAME verify.sedimentation_column_200ms COMMAND test_dense_closure sedimentation_200ms
         ${CMAKE_SOURCE_DIR}/parameters/sedimentation_column_1d.prm)
set_tests_properties(verify.sedimentation_column_200ms PROPERTIES LABELS verify TIMEOUT 600)
