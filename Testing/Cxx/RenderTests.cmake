# Render-pass tests: image regressions, accuracy, VTK users' complaints, and
# the stability suite. Each test runs through headless.sh (a private Xvfb
# when DISPLAY is unset).
include(GoogleTest)
math(EXPR _ss_render_timeout "300 * ${SOFTSHADOWS_TIMEOUT_SCALE}")
function(ss_render_test name label)
  add_executable(${name} ${name}.cxx ssRenderTestUtilities.cxx)
  target_link_libraries(${name} PRIVATE
    SoftShadows::RenderingOpenGL2 SoftShadows::RenderingCore
    VTK::TestingRendering VTK::FiltersSources VTK::RenderingOpenGL2 VTK::InteractionStyle
    GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE
    "SS_BASELINE_DIR=\"${SOFTSHADOWS_BASELINE_DIR}\""
    "SS_TEMP_DIR=\"${SOFTSHADOWS_TEST_OUTPUT_DIR}\"")
  target_compile_options(${name} PRIVATE ${SOFTSHADOWS_WARNINGS})
  vtk_module_autoinit(TARGETS ${name} MODULES VTK::RenderingOpenGL2 VTK::InteractionStyle)
  set_target_properties(${name} PROPERTIES CROSSCOMPILING_EMULATOR "${SOFTSHADOWS_HEADLESS}")
  gtest_discover_tests(${name}
    TEST_PREFIX "${label}."
    DISCOVERY_MODE PRE_TEST
    # listing the tests starts a private Xvfb (headless.sh) and a python
    # probe of its socket: more than GoogleTest's default 5 s on a loaded
    # machine, where the whole label then failed to be listed
    DISCOVERY_TIMEOUT 120
    PROPERTIES LABELS "${label}" TIMEOUT ${_ss_render_timeout})
endfunction()
ss_render_test(TestSoftShadowPass render)
ss_render_test(TestPVSMPass render)
ss_render_test(TestGearsGL render)
ss_render_test(TestStability stability)
ss_render_test(TestVPCSS render)
target_link_libraries(TestVPCSS PRIVATE VTK::RenderingVolumeOpenGL2)
vtk_module_autoinit(TARGETS TestVPCSS MODULES VTK::RenderingVolumeOpenGL2)
ss_render_test(TestVPCSSReceivers render)
ss_render_test(TestSoftShadowPassControls render)
ss_render_test(TestASMPass render)
ss_render_test(TestBadLights stability)
ss_render_test(TestTiledRendering render)
ss_render_test(TestShadowViews render)
ss_render_test(TestClippingRange render)
target_link_libraries(TestClippingRange PRIVATE VTK::FiltersGeneral VTK::CommonTransforms)
target_link_libraries(TestShadowViews PRIVATE VTK::IOImage)
ss_render_test(TestPreparedCasters render)
target_link_libraries(TestPreparedCasters PRIVATE SoftShadows::Filters VTK::FiltersCore VTK::CommonTransforms)
# The real-mesh image set (issue 17): smooth-shaded meshes, every method
# against GEARS; label realmesh (Documentation/stability.md).
ss_render_test(TestRealMeshes realmesh)
target_link_libraries(TestRealMeshes PRIVATE SoftShadowsScene SoftShadows::IO
  VTK::FiltersCore VTK::FiltersGeneral VTK::ImagingCore)
target_compile_definitions(TestRealMeshes PRIVATE
  "SS_MESH_DIR=\"${PROJECT_SOURCE_DIR}/Data/Meshes/generated\"")
