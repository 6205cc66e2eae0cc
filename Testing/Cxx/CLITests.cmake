# Command-line program: bad input gets one clear error line and exit code 2;
# good runs write the picture, buffers and stats of DESIGN.md.
set(_ss_data "${PROJECT_SOURCE_DIR}/Testing/Data")
set(_ss_expect "${PROJECT_SOURCE_DIR}/Testing/expect_error.sh")
set(_ss_cli "$<TARGET_FILE:softshadows>")
set(_ss_out "${SOFTSHADOWS_TEST_OUTPUT_DIR}")

function(ss_cli_error name regex)
  add_test(NAME cli.error.${name} COMMAND "${_ss_expect}" "${regex}" -- ${ARGN})
  set_tests_properties(cli.error.${name} PROPERTIES LABELS "cli" TIMEOUT 60)
endfunction()

set(_bad "${_ss_data}/BadScenes")
ss_cli_error(missing_scene "nope\\.json: cannot open" ${_ss_cli} render "${_bad}/nope.json")
ss_cli_error(malformed_json "malformed\\.json: invalid JSON" ${_ss_cli} render "${_bad}/malformed.json")
ss_cli_error(unknown_key "objects\\[0\\]\\.radious: unknown key" ${_ss_cli} render "${_bad}/unknown_key.json")
ss_cli_error(wrong_type "image\\.width: expected an integer" ${_ss_cli} render "${_bad}/wrong_type.json")
ss_cli_error(missing_mesh "objects\\[0\\]\\.mesh: mesh file not found" ${_ss_cli} render "${_bad}/missing_mesh.json")
ss_cli_error(not_a_mesh "objects\\[0\\]\\.mesh: could not read" ${_ss_cli} render "${_bad}/not_a_mesh.json")
ss_cli_error(zero_light_normal "lights\\[0\\]\\.normal: expected a non-zero vector" ${_ss_cli} render "${_bad}/zero_normal.json")
ss_cli_error(negative_light_size "lights\\[0\\]\\.size: expected an array of 2 non-negative" ${_ss_cli} render "${_bad}/negative_size.json")
ss_cli_error(string_number "lights\\[0\\]\\.position\\[1\\]: expected a number" ${_ss_cli} render "${_bad}/string_number.json")
ss_cli_error(unknown_light_type "lights\\[0\\]\\.type: unknown light type" ${_ss_cli} render "${_bad}/unknown_light.json")
ss_cli_error(bad_triangle_index "triangles\\[0\\]: vertex index out of range" ${_ss_cli} render "${_bad}/bad_index.json")
ss_cli_error(two_sources "objects\\[0\\]: expected exactly one of" ${_ss_cli} render "${_bad}/two_sources.json")
set(_demo "${PROJECT_SOURCE_DIR}/Data/Scenes/demo.json")
ss_cli_error(unknown_method "--method: unknown method 'fancy'" ${_ss_cli} render "${_demo}" --method fancy)
ss_cli_error(later_method "--method gears: not implemented yet" ${_ss_cli} render "${_demo}" --method gears)
ss_cli_error(bad_size "--size: expected WxH" ${_ss_cli} render "${_demo}" --size 640by480)
ss_cli_error(light_out_of_range "--light 3: out of range" ${_ss_cli} render "${_demo}" --size 64x48 --light 3)
ss_cli_error(unknown_option "--option: unknown key 'sharpness'" ${_ss_cli} render "${_demo}" --option sharpness=3)
ss_cli_error(vtk_visibility "--method vtk: --visibility and --positions are not available" ${_ss_cli} render "${_demo}" --method vtk --visibility "${_ss_out}/x.pfm")
ss_cli_error(unknown_command "unknown command 'draw'" ${_ss_cli} draw "${_demo}")

add_executable(ssCheckOutputs ssCheckOutputs.cxx)
target_link_libraries(ssCheckOutputs PRIVATE SoftShadowsScene nlohmann_json::nlohmann_json)
target_compile_options(ssCheckOutputs PRIVATE ${SOFTSHADOWS_WARNINGS})

# Good runs: render (DISPLAY unset: the program starts its own Xvfb), then check.
function(ss_cli_render name scene mode)
  set(_p "${_ss_out}/cli_${name}")
  add_test(NAME cli.render.${name}
    COMMAND env -u DISPLAY ${_ss_cli} render "${scene}" --output "${_p}.png"
      --visibility "${_p}_v.pfm" --positions "${_p}_p.pfm" --stats "${_p}.json" --frames 2 ${ARGN})
  add_test(NAME cli.check.${name}
    COMMAND ssCheckOutputs "${_p}.json" "${_p}_v.pfm" "${_p}_p.pfm" ${mode})
  set_tests_properties(cli.render.${name} PROPERTIES LABELS "cli" TIMEOUT 300 FIXTURES_SETUP cli_${name})
  set_tests_properties(cli.check.${name} PROPERTIES LABELS "cli" FIXTURES_REQUIRED cli_${name})
endfunction()
ss_cli_render(demo_pcss "${_demo}" soft --method pcss)
ss_cli_render(demo_auto "${_demo}" soft)
ss_cli_render(empty_scene "${_ss_data}/GoodScenes/empty.json" empty)
ss_cli_render(nan_mesh "${_ss_data}/GoodScenes/nan_mesh.json" soft --method pcss --size 320x240)
add_test(NAME cli.render.vtk_method
  COMMAND env -u DISPLAY ${_ss_cli} render "${_demo}" --method vtk --size 160x120 --output "${_ss_out}/cli_vtk.png")
set_tests_properties(cli.render.vtk_method PROPERTIES LABELS "cli" TIMEOUT 120)

# Benchmark smoke run: a tiny scene, a few settings; asserts the report, data
# and plot are produced and sane (not timings).
add_test(NAME cli.bench.smoke
  COMMAND env -u DISPLAY ${_ss_cli} bench --smoke --scenes "${PROJECT_SOURCE_DIR}/Data/Scenes/sphere_plane.json"
    --size 160x120 --frames 1 --reference-samples 8 --out "${_ss_out}/bench_smoke")
add_test(NAME cli.bench.smoke_check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_bench.py" "${_ss_out}/bench_smoke")
set_tests_properties(cli.bench.smoke PROPERTIES LABELS "cli;bench" TIMEOUT 300 FIXTURES_SETUP bench_smoke)
set_tests_properties(cli.bench.smoke_check PROPERTIES LABELS "cli;bench" FIXTURES_REQUIRED bench_smoke)
