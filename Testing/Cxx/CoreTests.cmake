# Unit tests of Rendering/Core: no window, no GL. One executable, one source
# file per Core header family.
add_executable(TestSoftShadowsCore
  TestSSLightFrame.cxx
  TestSSCoverage.cxx
  TestSSPCSS.cxx
  TestSSAnalytic.cxx
  TestSSEffectPlanner.cxx
  TestSSShadowView.cxx
  TestSSReference.cxx
  TestSSReferenceISA.cxx
  TestSSGEARS.cxx
  TestSSGEARSCulling.cxx
  TestSSGEARSISA.cxx
  TestSSGEARSSilhouette.cxx
  TestSSGEARSWinding.cxx
  TestSSGEARSFiltered.cxx
  TestSSGEARSFarLight.cxx
  TestSSGearsPieces.cxx
  TestSSPVSM.cxx
  TestSSMetrics.cxx
  TestSSCasterClusters.cxx
  TestSSClusterBounds.cxx
  TestSSBlockerSearchWindow.cxx
  TestSSConservativeMap.cxx
  TestSSPVSMTileReads.cxx
  TestSSAVSM.cxx
  TestSSVPCSS.cxx
  TestSSVolumeGrid.cxx
  TestSSSolveProgress.cxx
  TestSSASM.cxx
  TestSSSolverOptions.cxx)
find_package(TBB REQUIRED)
target_link_libraries(TestSoftShadowsCore PRIVATE SoftShadows::RenderingCore TBB::tbb GTest::gtest_main)
target_compile_options(TestSoftShadowsCore PRIVATE ${SOFTSHADOWS_WARNINGS} -Wpedantic)
include(GoogleTest)
math(EXPR _ss_core_timeout "120 * ${SOFTSHADOWS_TIMEOUT_SCALE}")
gtest_discover_tests(TestSoftShadowsCore TEST_PREFIX "core." PROPERTIES LABELS "core" TIMEOUT ${_ss_core_timeout})

# Unit tests of IO/Core (the file-format guards; no VTK).
add_executable(TestSoftShadowsIOCore TestSSMeshCheck.cxx)
target_link_libraries(TestSoftShadowsIOCore PRIVATE SoftShadows::IOCore GTest::gtest_main)
target_compile_options(TestSoftShadowsIOCore PRIVATE ${SOFTSHADOWS_WARNINGS} -Wpedantic)
gtest_discover_tests(TestSoftShadowsIOCore TEST_PREFIX "iocore." PROPERTIES LABELS "core" TIMEOUT 60)
