# The examples of Documentation/*.md as written (issue 24), run from a scratch
# directory laid out like the source tree (build/ and Data/Meshes link to the
# real ones) so that relative paths in the snippets hold and no output lands
# in the source tree.
set(_ss_docroot "${SOFTSHADOWS_TEST_OUTPUT_DIR}/docroot")
file(MAKE_DIRECTORY "${_ss_docroot}/Data/Scenes")
if (NOT EXISTS "${_ss_docroot}/build")
  file(CREATE_LINK "${PROJECT_BINARY_DIR}" "${_ss_docroot}/build" SYMBOLIC)
endif ()
if (NOT EXISTS "${_ss_docroot}/Data/Meshes")
  file(CREATE_LINK "${PROJECT_SOURCE_DIR}/Data/Meshes" "${_ss_docroot}/Data/Meshes" SYMBOLIC)
endif ()
set(_ss_doc "${PROJECT_SOURCE_DIR}/Testing/run_doc_block.sh")
set(_ss_docs "${PROJECT_SOURCE_DIR}/Documentation")
set(_ss_doc_env "PYTHONPATH=${CMAKE_BINARY_DIR}/python;LD_LIBRARY_PATH=${CMAKE_BINARY_DIR}/lib")

# scene-format.md: the example scene, saved as Data/Scenes/example.json, renders
add_test(NAME doc.scene_format
  COMMAND "${_ss_doc}" "${_ss_docs}/scene-format.md" json 1 --
    sh -c "cp \"$1\" Data/Scenes/example.json && build/bin/softshadows render Data/Scenes/example.json --size 160x120 --output example.png && test -s example.png" sh
  WORKING_DIRECTORY "${_ss_docroot}")
set_tests_properties(doc.scene_format PROPERTIES LABELS "doc;cli" TIMEOUT 120)
# its volume example (issue 20): a vtkVolume that the planner gives vpcss and that
# casts a shadow (the stats count it)
add_test(NAME doc.scene_format_volume
  COMMAND "${_ss_doc}" "${_ss_docs}/scene-format.md" json 2 --
    sh -c "build/bin/softshadows render \"$2\" --size 160x120 --output \"$1/doc_volume.png\" --stats \"$1/doc_volume.json\" && grep -q '\"volumes\": 1' \"$1/doc_volume.json\" && grep -q '\"vpcss\"' \"$1/doc_volume.json\"" sh "${SOFTSHADOWS_TEST_OUTPUT_DIR}"
  WORKING_DIRECTORY "${_ss_docroot}")
set_tests_properties(doc.scene_format_volume PROPERTIES LABELS "doc;cli" TIMEOUT 120)

if (SOFTSHADOWS_SYSTEM_PYTHON AND TARGET SoftShadowsRenderingOpenGL2Python)
  add_test(NAME doc.python_pass
    COMMAND "${_ss_doc}" "${_ss_docs}/python.md" python 1 -- "${SOFTSHADOWS_HEADLESS}" "${SOFTSHADOWS_SYSTEM_PYTHON}"
    WORKING_DIRECTORY "${_ss_docroot}")
  add_test(NAME doc.python_reader
    COMMAND "${_ss_doc}" "${_ss_docs}/python.md" python 2 -- "${SOFTSHADOWS_SYSTEM_PYTHON}"
    WORKING_DIRECTORY "${_ss_docroot}")
  set_tests_properties(doc.python_pass PROPERTIES PASS_REGULAR_EXPRESSION "light 0: pcss - requested pcss")
  set_tests_properties(doc.python_pass doc.python_reader PROPERTIES LABELS "doc;python" TIMEOUT 120
    ENVIRONMENT "${_ss_doc_env}")
endif ()

if (PVPYTHON_EXECUTABLE AND SOFTSHADOWS_HAVE_PARAVIEW)
  add_test(NAME doc.paraview_view
    COMMAND "${_ss_doc}" "${_ss_docs}/paraview.md" python 1 --
      "${SOFTSHADOWS_HEADLESS}" "${PVPYTHON_EXECUTABLE}" --force-offscreen-rendering
    WORKING_DIRECTORY "${_ss_docroot}")
  set_tests_properties(doc.paraview_view PROPERTIES PASS_REGULAR_EXPRESSION "light 4: pcss - requested pcss")
  add_test(NAME doc.paraview_reader
    COMMAND "${_ss_doc}" "${_ss_docs}/paraview.md" python 2 --
      "${SOFTSHADOWS_HEADLESS}" "${PVPYTHON_EXECUTABLE}" --force-offscreen-rendering
    WORKING_DIRECTORY "${_ss_docroot}")
  set_tests_properties(doc.paraview_reader PROPERTIES PASS_REGULAR_EXPRESSION "768 triangles")
  set_tests_properties(doc.paraview_view doc.paraview_reader PROPERTIES LABELS "doc;paraview" TIMEOUT 300
    ENVIRONMENT "${_ss_doc_env}")
endif ()
