# Render-pass tests: image regressions, accuracy, VTK users' complaints.
add_executable(TestSoftShadowPass TestSoftShadowPass.cxx)
target_link_libraries(TestSoftShadowPass PRIVATE
  SoftShadows::RenderingOpenGL2 SoftShadows::RenderingCore
  VTK::TestingRendering VTK::FiltersSources VTK::RenderingOpenGL2 VTK::InteractionStyle
  GTest::gtest_main)
target_compile_definitions(TestSoftShadowPass PRIVATE
  "SS_BASELINE_DIR=\"${SOFTSHADOWS_BASELINE_DIR}\""
  "SS_TEMP_DIR=\"${SOFTSHADOWS_TEST_OUTPUT_DIR}\"")
target_compile_options(TestSoftShadowPass PRIVATE ${SOFTSHADOWS_WARNINGS})
vtk_module_autoinit(TARGETS TestSoftShadowPass MODULES VTK::RenderingOpenGL2 VTK::InteractionStyle)
set_target_properties(TestSoftShadowPass PROPERTIES CROSSCOMPILING_EMULATOR "${SOFTSHADOWS_HEADLESS}")
include(GoogleTest)
gtest_discover_tests(TestSoftShadowPass
  TEST_PREFIX "render."
  DISCOVERY_MODE PRE_TEST
  PROPERTIES LABELS "render" TIMEOUT 300
  EXTRA_ARGS "")
