# SoftShadows::Filters: caster preparation and light-visibility baking, no
# window and no GPU.
add_executable(TestSoftShadowsFilters
  TestShadowCasterPreparation.cxx
  TestLightVisibilityFilter.cxx)
find_package(TBB REQUIRED)
target_link_libraries(TestSoftShadowsFilters PRIVATE
  SoftShadows::Filters
  SoftShadows::RenderingOpenGL2
  SoftShadows::RenderingCore
  VTK::CommonCore
  VTK::CommonDataModel
  VTK::FiltersSources
  VTK::RenderingCore
  TBB::tbb
  GTest::gtest_main)
target_compile_definitions(TestSoftShadowsFilters PRIVATE _USE_MATH_DEFINES)
target_compile_options(TestSoftShadowsFilters PRIVATE ${SOFTSHADOWS_WARNINGS})
gtest_discover_tests(TestSoftShadowsFilters TEST_PREFIX "filters." PROPERTIES LABELS "filters" TIMEOUT 300)
