# Unit tests of Rendering/Core: no window, no GL.
add_executable(TestSoftShadowsCore TestSoftShadowsCore.cxx)
target_link_libraries(TestSoftShadowsCore PRIVATE SoftShadows::RenderingCore GTest::gtest_main)
target_compile_options(TestSoftShadowsCore PRIVATE ${SOFTSHADOWS_WARNINGS})
include(GoogleTest)
gtest_discover_tests(TestSoftShadowsCore TEST_PREFIX "core." PROPERTIES LABELS "core" TIMEOUT 120)
