/* verification_cases.h - the verification cases of test_verification: name, the call that runs
 * it, its CTest labels and time limit (s). One list for the program (test_verification.c expands
 * it into its dispatch table) and for CMake (tests/CMakeLists.txt reads the CASE lines).
 */
/* MODEL.md 12: exact answers */
CASE(linear_strip, LinearStrip(), "verification", 300)
CASE(crimp_knee, CrimpKnee(), "verification", 300)
CASE(wave_speed, WaveSpeed(), "verification", 300)
CASE(damping_slowest, DampingSlowest(), "verification", 60)
CASE(transverse_load, TransverseLoad(), "verification", 300)
CASE(stable_095, Stable095(), "verification", 300)
CASE(unstable_110, Unstable110(), "verification", 300)
CASE(paper_parasitic, PaperParasitic(), "verification", 300)
/* the measured stable limit (spectrum.c) against an exact spectrum, and the bound against it */
CASE(spectrum_chain, SpectrumChain(), "verification", 120)
CASE(spectrum_scenes, SpectrumScenes(), "verification", 300)
CASE(spectrum_dense, SpectrumDense(), "verification", 120)
/* the balance test per crossing against exact ratios, and after a relaxation (balance.c) */
CASE(balance_crossings, BalanceCrossingsCase(), "verification", 120)
/* the te steps' balance test: at rest, not only balanced (mutation test of integrate.c) */
CASE(balanced_at_rest, BalancedAtRest(), "verification", 120)
/* scenes with shapes, clamp regions, rigid bodies, clamp and grip lines and the grip's path */
CASE(square_net, SquareNet(), "verification;scenes", 120)
CASE(bias_extension, BiasExtension(), "verification;scenes", 120)
CASE(plane_rest, RestOnSupport(PETSC_FALSE), "verification;scenes", 120)
CASE(pedestal_rest, RestOnSupport(PETSC_TRUE), "verification;scenes", 120)
CASE(friction_incline, FrictionIncline(), "verification;scenes", 120)
CASE(grip_lines, GripLines(), "verification;scenes", 120)
CASE(grip_path, GripPath(), "verification;scenes", 120)
CASE(drape_measure, DrapeMeasure(), "verification;scenes", 120)
/* the speed-ups (MODEL.md 8-10) against exact answers and the all-off reference */
CASE(linear_prediction, LinearPrediction(), "speedups", 300)
CASE(speedups_curve, SpeedupsCurve(), "speedups", 300)
