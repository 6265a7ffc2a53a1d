"""Test-suite settings shared by every folder: the ``slow`` marker.

``python -m pytest`` (the README's command, CI) runs every test; ``python -m pytest -m "not slow"``
skips the tests listed here, each of which took 0.5 s or more on 2 cores (mostly MPM runs and
Taichi compiles), and the modules whose shared fixtures run the MPM solver, so that the rest runs in under a minute. The list is kept here rather than as
decorators so that the marker does not touch the test files themselves.
"""

import pytest

SLOW = (
    # whole modules: their shared fixtures run the MPM solver
    "tests/validation/test_mpm_mu_i.py",
    "tests/validation/test_mpm_plate_drag.py",
    "tests/validation/test_mpm_locomotion.py",
    "tests/validation/test_mpm_deterministic_sums.py",
    "tests/unit/test_cli_mpm.py::test_resume_writes_to_the_folder_it_is_given_after_a_move",
    "tests/unit/test_bulldozing.py::test_force_model_adds_the_term_on_both_paths",
    "tests/unit/test_mpm_snapshots.py::test_collection_lists_every_snapshot_at_its_time",
    "tests/validation/test_mpm_simd_lanes.py::test_nonlocal_sources_match_the_one_point_kernel",
    "tests/regression/test_bulldozing_calibration.py::test_one_bulldozing_coefficient_brings_the_paper_drft_to_the_settled_mpm_wheel",
    "tests/unit/test_backend_arch.py::test_a_bad_arch_in_the_environment_is_refused_by_name",
    "tests/unit/test_backend_arch.py::test_a_requested_gpu_reports_the_backend_that_really_runs",
    "tests/unit/test_backend_arch.py::test_bench_mpm_refuses_bad_options_before_compute",
    "tests/unit/test_backend_arch.py::test_gpu_check_on_the_cpu_against_itself_finds_no_difference",
    "tests/unit/test_backend_arch.py::test_the_cpu_is_no_fallback",
    "tests/unit/test_backend_arch.py::test_the_environment_overrides_the_callers_arch",
    "tests/unit/test_calibration.py::test_calibrate_recovers_a_known_bulldozing_coefficient_and_leave_one_out_predicts_each_omega",
    "tests/unit/test_calibration.py::test_calibrate_recovers_known_xi_and_psi",
    "tests/unit/test_calibration.py::test_cli_calibrate_check_keeps_the_checked_scenarios_own_force_model",
    "tests/unit/test_calibration.py::test_cli_calibrate_checks_a_single_omega_and_refuses_a_bad_check_before_the_fit",
    "tests/unit/test_calibration.py::test_cli_calibrate_leave_one_out",
    "tests/unit/test_calibration.py::test_cli_calibrate_writes_json_csv_png",
    "tests/unit/test_calibration.py::test_local_fits_on_dask_give_the_serial_result",
    "tests/unit/test_cli_mpm.py::test_a_scenario_toml_runs_in_mpm_as_in_drft",
    "tests/unit/test_cli_mpm.py::test_run_on_its_own_folder_goes_on_a_later_end_extends_it_and_another_config_is_refused",
    "tests/unit/test_cli_mpm.py::test_run_writes_a_run_folder_and_resume_extends_it",
    "tests/unit/test_cli_mpm.py::test_steady_marks_its_folder_finished_and_refuses_another_configuration_on_it",
    "tests/unit/test_cli_mpm.py::test_treadmill_reaches_the_run_settings_and_a_bad_one_is_refused_before_compute",
    "tests/unit/test_demo.py::test_demo_writes_table_and_png",
    "tests/unit/test_examples.py::test_calibrate_drft",
    "tests/unit/test_examples.py::test_mpm_quick_wheel",
    "tests/unit/test_examples.py::test_mpm_rft_map",
    "tests/unit/test_examples.py::test_mpm_run_from_toml",
    "tests/unit/test_figures.py::test_fig7bc_quick_csv_is_nondimensionalised",
    "tests/unit/test_layout.py::test_the_package_does_not_import_research",
    "tests/unit/test_mpm_flip.py::test_flip_keeps_a_free_points_velocity_where_apic_replaces_it",
    "tests/unit/test_mpm_flip.py::test_flip_runs_the_vectorised_kernels_and_the_fixed_point_sums_agree",
    "tests/unit/test_mpm_fluidity_law.py::test_sweeps_converge_to_the_direct_solve_with_free_nodes_and_neumann_edges",
    "tests/unit/test_mpm_fluidity_law.py::test_sweeps_on_the_box_of_the_material_equal_sweeps_on_every_node",
    "tests/unit/test_mpm_grid_box.py::test_atomic_and_chunked_particle_passes_agree",
    "tests/unit/test_mpm_linear_shape.py::test_a_linear_bed_at_rest_holds_the_hydrostatic_stress",
    "tests/unit/test_mpm_linear_shape.py::test_linear_and_quadratic_differ_and_the_fixed_point_sums_agree",
    "tests/unit/test_mpm_linear_shape.py::test_linear_g2p_gives_an_affine_fields_gradient_exactly_inside_the_patch",
    "tests/unit/test_mpm_snapshots.py::test_bodies_are_written_at_their_pose",
    "tests/unit/test_mpm_snapshots.py::test_particle_snapshot_has_the_fields",
    "tests/unit/test_mpm_window.py::test_the_fluidity_warm_start_moves_with_the_grains",
    "tests/unit/test_sweep.py::test_dask_matches_serial",
    "tests/validation/test_locomotion_paper.py::test_quasistatic_rft_round_wheel_v_proportional_to_omega",
    "tests/validation/test_mpm_bed_at_rest.py::test_mass_is_conserved",
    "tests/validation/test_mpm_deterministic_sums.py::test_a_restart_with_fixed_point_atomic_sums_reproduces_the_uninterrupted_run",
    "tests/validation/test_mpm_deterministic_sums.py::test_atomic_sums_in_fixed_point_repeat_bit_for_bit",
    "tests/validation/test_mpm_deterministic_sums.py::test_fixed_point_sums_agree_with_the_chunked_fixed_order_sums",
    "tests/validation/test_mpm_deterministic_sums.py::test_float_atomic_sums_are_still_there_when_asked_for",
    "tests/validation/test_mpm_device_bodies.py::test_a_restart_of_a_body_advanced_on_the_device_reproduces_the_run_bit_for_bit",
    "tests/validation/test_mpm_device_bodies.py::test_device_dynamics_follow_the_host_dynamics",
    "tests/validation/test_mpm_device_bodies.py::test_each_of_several_bodies_keeps_its_own_dynamics",
    "tests/validation/test_mpm_fluidity_runs.py::test_a_killed_nonlocal_run_resumes_on_the_uninterrupted_track",
    "tests/validation/test_mpm_fluidity_runs.py::test_the_atomic_sources_kernel_drags_as_the_chunked_one",
    "tests/validation/test_mpm_fluidity_runs.py::test_with_poppy_seed_grains_the_nonlocal_law_drags_as_the_paper_law_within_a_few_per_cent",
    "tests/validation/test_mpm_gate.py::test_gate_holds_the_column_then_releases_it",
    "tests/validation/test_mpm_locomotion.py::test_a_killed_free_wheel_with_the_nonlocal_law_resumes_on_the_uninterrupted_track",
    "tests/validation/test_mpm_locomotion.py::test_a_killed_treadmill_run_resumes_on_the_uninterrupted_track",
    "tests/validation/test_mpm_locomotion.py::test_finished_run_with_a_later_t_max_goes_on_from_its_end_and_matches_a_run_that_long",
    "tests/validation/test_mpm_locomotion.py::test_killed_run_resumes_from_its_checkpoint_and_matches_the_uninterrupted_run",
    "tests/validation/test_mpm_locomotion.py::test_runner_rises_as_omega_grows",
    "tests/validation/test_mpm_locomotion.py::test_sweep_dispatches_to_mpm_and_survives_a_bad_point",
    "tests/validation/test_mpm_locomotion.py::test_the_treadmill_in_a_1_m_box_gives_the_2_m_box_wheel",
    "tests/validation/test_mpm_locomotion.py::test_wheel_slips_more_and_sinks_more_as_omega_grows",
    "tests/validation/test_mpm_locomotion.py::test_with_the_paper_groups_transfer_the_wheel_keeps_the_trends",
    "tests/validation/test_mpm_mu_i.py::test_mu_i_raises_the_drag_more_for_larger_grains_and_faster_plates",
    "tests/validation/test_mpm_plate_drag.py::test_slow_drag_grows_linearly_with_depth",
    "tests/validation/test_mpm_restart.py::test_a_run_keeps_its_end_state_and_an_extension_goes_on_from_it",
    "tests/validation/test_mpm_restart.py::test_checkpoint_from_before_the_front_rear_split_resumes",
    "tests/validation/test_mpm_restart.py::test_restart_reproduces_uninterrupted_run",
    "tests/validation/test_mpm_rft_map_plates.py::test_mirrored_plate_feels_the_mirrored_force",
    "tests/validation/test_mpm_rft_map_plates.py::test_plate_pushed_down_meets_the_footing_bearing_capacity",
    "tests/validation/test_mpm_rft_map_plates.py::test_pulled_up_plate_lifts_little_more_than_its_overburden",
    "tests/validation/test_mpm_simd_lanes.py::test_a_float64_run_steps_on_the_one_point_kernels",
    "tests/validation/test_mpm_simd_lanes.py::test_one_g2p_step_matches_the_one_point_kernel",
    "tests/validation/test_mpm_simd_lanes.py::test_the_step_compiles_the_kernel_once_as_vector_code",
    "tests/validation/test_mpm_simd_lanes.py::test_wheel_run_follows_the_one_point_run",
    "tests/validation/test_mpm_slope.py::test_block_slides_only_beyond_friction",
    "tests/validation/test_mpm_wheel.py::test_contact_band_carries_the_wheel_higher",
    "tests/validation/test_mpm_wheel.py::test_driven_grousered_wheel_moves_forward",
    "tests/validation/test_mpm_wheel.py::test_resting_wheel_weight_is_carried_by_contact",
)


def pytest_collection_modifyitems(config, items):
    for item in items:
        test = item.nodeid.split("[")[0]
        if test in SLOW or test.split("::")[0] in SLOW:
            item.add_marker(pytest.mark.slow)
