# The programs of Examples/ (issue 24), each run as a user would and each
# saving a picture; the C++ one is built against the installed package by
# install.find_package_example.
set(_ss_py_env "PYTHONPATH=${CMAKE_BINARY_DIR}/python;LD_LIBRARY_PATH=${CMAKE_BINARY_DIR}/lib")
if (SOFTSHADOWS_SYSTEM_PYTHON AND TARGET SoftShadowsRenderingOpenGL2Python)
  add_test(NAME example.python_vtk
    COMMAND "${SOFTSHADOWS_HEADLESS}" ${SOFTSHADOWS_TEST_PRELOAD} "${SOFTSHADOWS_SYSTEM_PYTHON}"
      "${PROJECT_SOURCE_DIR}/Examples/python/soft_shadows.py" ""
      "${SOFTSHADOWS_TEST_OUTPUT_DIR}/ExamplePythonVTK.png")
  set_tests_properties(example.python_vtk PROPERTIES LABELS "example;python" TIMEOUT 120
    ENVIRONMENT "${_ss_py_env}")
endif ()
if (PVPYTHON_EXECUTABLE AND SOFTSHADOWS_HAVE_PARAVIEW)
  add_test(NAME example.pvpython
    COMMAND "${SOFTSHADOWS_HEADLESS}" ${SOFTSHADOWS_TEST_PRELOAD} "${PVPYTHON_EXECUTABLE}" --force-offscreen-rendering
      "${PROJECT_SOURCE_DIR}/Examples/pvpython/soft_shadows_view.py" "${SOFTSHADOWS_PLUGIN_PATH}"
      "${SOFTSHADOWS_TEST_OUTPUT_DIR}/ExamplePvpython.png")
  # the state names its mesh relative to the source tree, as a user opens it
  add_test(NAME example.paraview_state
    COMMAND "${SOFTSHADOWS_HEADLESS}" ${SOFTSHADOWS_TEST_PRELOAD} "${PVPYTHON_EXECUTABLE}" --force-offscreen-rendering
      "${PROJECT_SOURCE_DIR}/Examples/state/open_state.py" "${SOFTSHADOWS_PLUGIN_PATH}"
      "${SOFTSHADOWS_TEST_OUTPUT_DIR}/ExampleState.png"
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}")
  set_tests_properties(example.pvpython example.paraview_state PROPERTIES LABELS "example;paraview" TIMEOUT 300
    ENVIRONMENT "${_ss_py_env}")
endif ()
