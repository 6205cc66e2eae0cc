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
# More bad input, written at configure time into the build tree: each must
# give the one error line first (no VTK or OpenMesh log line before it).
set(_gen "${_ss_out}/GeneratedBadScenes")
file(MAKE_DIRECTORY "${_gen}")
file(WRITE "${_gen}/number_overflow.json" "{\"image\": {\"width\": 1e400}, \"objects\": []}\n")
file(WRITE "${_gen}/zero_width.json" "{\"image\": {\"width\": 0, \"height\": 10}, \"objects\": []}\n")
file(WRITE "${_gen}/empty.vtp" "")
file(WRITE "${_gen}/empty_vtp.json" "{\"objects\": [{\"mesh\": \"empty.vtp\"}]}\n")
file(WRITE "${_gen}/bad_index.off" "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
file(WRITE "${_gen}/bad_off.json" "{\"objects\": [{\"mesh\": \"bad_index.off\"}]}\n")
file(WRITE "${_gen}/zero_scale.json"
  "{\"objects\": [{\"primitive\": \"sphere\", \"transform\": {\"scale\": [1, 0, 1]}}]}\n")
# Issue 17: lights VTK's float shading cannot render (a black picture with
# exit 0 before) are clear errors naming the key.
file(WRITE "${_gen}/light_intensity_1e39.json"
  "{\"lights\": [{\"type\": \"rect\", \"center\": [0,0,5], \"normal\": [0,0,-1], \"intensity\": 1e39}], \"objects\": [{\"primitive\": \"sphere\"}]}\n")
file(WRITE "${_gen}/light_position_1e30.json"
  "{\"lights\": [{\"type\": \"point\", \"position\": [0,0,1e30]}], \"objects\": [{\"primitive\": \"sphere\"}]}\n")
file(WRITE "${_gen}/light_center_1e30.json"
  "{\"lights\": [{\"type\": \"rect\", \"center\": [1e30,0,5], \"normal\": [0,0,-1]}], \"objects\": [{\"primitive\": \"sphere\"}]}\n")
ss_cli_error(light_intensity_1e39 "lights\\[0\\]\\.intensity: intensity beyond the float range" ${_ss_cli} render "${_gen}/light_intensity_1e39.json")
ss_cli_error(light_position_1e30 "lights\\[0\\]\\.position: light coordinate 1e\\+30 beyond 1e18" ${_ss_cli} render "${_gen}/light_position_1e30.json")
ss_cli_error(light_center_1e30 "lights\\[0\\]\\.center: light coordinate 1e\\+30 beyond 1e18" ${_ss_cli} render "${_gen}/light_center_1e30.json")
ss_cli_error(number_overflow "number_overflow\\.json: invalid JSON: .*number overflow" ${_ss_cli} render "${_gen}/number_overflow.json")
ss_cli_error(zero_image_size "zero_width\\.json: image\\.width: expected an integer in \\[1, " ${_ss_cli} render "${_gen}/zero_width.json")
ss_cli_error(unreadable_vtp "empty_vtp\\.json: objects\\[0\\]\\.mesh: could not read" ${_ss_cli} render "${_gen}/empty_vtp.json")
ss_cli_error(bad_off "bad_off\\.json: objects\\[0\\]\\.mesh: could not read" ${_ss_cli} render "${_gen}/bad_off.json")
ss_cli_error(zero_scale "objects\\[0\\]\\.transform\\.scale: expected non-zero" ${_ss_cli} render "${_gen}/zero_scale.json")
# Volume objects (issue 20): each bad key or value is one error line naming it.
set(_vol_tf "\"opacity_function\": [[0, 0], [1, 0.5]]")
file(WRITE "${_gen}/volume_no_tf.json" "{\"objects\": [{\"volume\": {\"field\": \"box\"}}]}\n")
file(WRITE "${_gen}/volume_tf_order.json"
  "{\"objects\": [{\"volume\": {\"field\": \"box\"}, \"opacity_function\": [[1, 0], [0, 0.5]]}]}\n")
file(WRITE "${_gen}/volume_tf_opacity.json"
  "{\"objects\": [{\"volume\": {\"field\": \"box\"}, \"opacity_function\": [[0, 0], [1, 1.5]]}]}\n")
file(WRITE "${_gen}/volume_field.json" "{\"objects\": [{\"volume\": {\"field\": \"smoke\"}, ${_vol_tf}}]}\n")
file(WRITE "${_gen}/volume_resolution.json"
  "{\"objects\": [{\"volume\": {\"field\": \"gaussian\", \"resolution\": [8, 1, 8]}, ${_vol_tf}}]}\n")
file(WRITE "${_gen}/volume_box_std_dev.json"
  "{\"objects\": [{\"volume\": {\"field\": \"box\", \"std_dev\": 0.2}, ${_vol_tf}}]}\n")
file(WRITE "${_gen}/volume_unknown_key.json"
  "{\"objects\": [{\"volume\": {\"field\": \"box\"}, ${_vol_tf}, \"receives_shadows\": true}]}\n")
file(WRITE "${_gen}/volume_two_sources.json"
  "{\"objects\": [{\"volume\": {\"field\": \"box\", \"file\": \"a.vti\"}, ${_vol_tf}}]}\n")
file(WRITE "${_gen}/volume_and_mesh.json"
  "{\"objects\": [{\"volume\": {\"field\": \"box\"}, \"primitive\": \"sphere\", ${_vol_tf}}]}\n")
file(WRITE "${_gen}/volume_missing_file.json" "{\"objects\": [{\"volume\": {\"file\": \"nope.vti\"}, ${_vol_tf}}]}\n")
file(WRITE "${_gen}/not_a_volume.vti" "<VTKFile type=\"ImageData\"> cut")
file(WRITE "${_gen}/volume_bad_file.json" "{\"objects\": [{\"volume\": {\"file\": \"not_a_volume.vti\"}, ${_vol_tf}}]}\n")
file(WRITE "${_gen}/volume_unit_distance.json"
  "{\"objects\": [{\"volume\": {\"field\": \"box\"}, ${_vol_tf}, \"unit_distance\": 0}]}\n")
ss_cli_error(volume_no_opacity_function "objects\\[0\\]\\.opacity_function: missing" ${_ss_cli} render "${_gen}/volume_no_tf.json")
ss_cli_error(volume_opacity_function_order "objects\\[0\\]\\.opacity_function\\[1\\]: scalars must increase" ${_ss_cli} render "${_gen}/volume_tf_order.json")
ss_cli_error(volume_opacity_range "objects\\[0\\]\\.opacity_function\\[1\\]: opacity 1\\.5.* outside \\[0, 1\\]" ${_ss_cli} render "${_gen}/volume_tf_opacity.json")
ss_cli_error(volume_unknown_field "objects\\[0\\]\\.volume\\.field: unknown field 'smoke'" ${_ss_cli} render "${_gen}/volume_field.json")
ss_cli_error(volume_resolution "objects\\[0\\]\\.volume\\.resolution\\[1\\]: expected an integer in \\[2, 512\\]" ${_ss_cli} render "${_gen}/volume_resolution.json")
ss_cli_error(volume_box_std_dev "objects\\[0\\]\\.volume\\.std_dev: unknown key" ${_ss_cli} render "${_gen}/volume_box_std_dev.json")
ss_cli_error(volume_receives_shadows "objects\\[0\\]\\.receives_shadows: unknown key" ${_ss_cli} render "${_gen}/volume_unknown_key.json")
ss_cli_error(volume_two_sources "objects\\[0\\]\\.volume: expected an object with exactly one of" ${_ss_cli} render "${_gen}/volume_two_sources.json")
ss_cli_error(volume_and_mesh "objects\\[0\\]: expected exactly one of .*\"volume\"" ${_ss_cli} render "${_gen}/volume_and_mesh.json")
ss_cli_error(volume_missing_file "objects\\[0\\]\\.volume\\.file: volume file not found" ${_ss_cli} render "${_gen}/volume_missing_file.json")
ss_cli_error(volume_bad_file "objects\\[0\\]\\.volume\\.file: could not read" ${_ss_cli} render "${_gen}/volume_bad_file.json")
ss_cli_error(volume_unit_distance "objects\\[0\\]\\.unit_distance: expected a positive number" ${_ss_cli} render "${_gen}/volume_unit_distance.json")

# Damaged mesh files (issue 18): each case of the issue's table gets one
# error line naming the scene key, the file and what is wrong, exit code 2,
# and no crash. The files are written at configure time.
set(_bm "${_ss_out}/BadMeshes")
execute_process(COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/make_bad_meshes.py" "${_bm}"
  "${PROJECT_SOURCE_DIR}/Data/Meshes/torus.off" RESULT_VARIABLE _bm_rc)
if (NOT _bm_rc EQUAL 0)
  message(FATAL_ERROR "Testing/make_bad_meshes.py failed")
endif ()
set(_mesh "objects\\[0\\]\\.mesh: could not read [^ ]*")
ss_cli_error(mesh.stl_random_bytes "${_mesh}random\\.stl: STL: binary STL header declares 3416378287 triangles .* but the file has 4096 bytes"
  ${_ss_cli} render "${_bm}/random_stl.json")
ss_cli_error(mesh.ply_header_no_data "${_mesh}nodata\\.ply: PLY: the header declares 3 vertices and 1 faces .* but only 0 bytes follow the header"
  ${_ss_cli} render "${_bm}/nodata_ply.json")
ss_cli_error(mesh.ply_cut_at_1mb "${_mesh}cut\\.ply: PLY: the header declares 40000 vertices and 79202 faces .* but only 999823 bytes follow"
  ${_ss_cli} render "${_bm}/cut_ply.json")
ss_cli_error(mesh.obj_index_zero "${_mesh}zero_index\\.obj: OBJ: line 4: 'f': vertex index 0 \\(OBJ indices start at 1\\)"
  ${_ss_cli} render "${_bm}/zero_index_obj.json")
ss_cli_error(mesh.obj_index_past_end "${_mesh}index_99\\.obj: OBJ: line 4: 'f': vertex index 99 out of range \\(1\\.\\.3 or -1\\.\\.-3\\)"
  ${_ss_cli} render "${_bm}/index_99_obj.json")
ss_cli_error(mesh.obj_relative_index "${_mesh}index_minus_99\\.obj: OBJ: line 4: 'f': vertex index -99 out of range"
  ${_ss_cli} render "${_bm}/index_minus_99_obj.json")
ss_cli_error(mesh.ply_huge_count "${_mesh}huge_count\\.ply: PLY: the header declares 999999999 vertices .* but only 26 bytes follow"
  ${_ss_cli} render "${_bm}/huge_count_ply.json")
ss_cli_error(mesh.ply_index_out_of_range "${_mesh}index_7\\.ply: PLY: line 13: face 0: vertex index 7 out of range \\[0, 2\\]"
  ${_ss_cli} render "${_bm}/index_7_ply.json")
ss_cli_error(mesh.off_cut "${_mesh}cut_82\\.off: OFF: the file ends after 82 of the 768 faces its header declares"
  ${_ss_cli} render "${_bm}/cut_82_off.json")
ss_cli_error(mesh.off_more_faces_than_held "${_mesh}more_faces\\.off: OFF: the file ends after 768 of the 1536 faces"
  ${_ss_cli} render "${_bm}/more_faces_off.json")
ss_cli_error(mesh.off_index_out_of_range "${_mesh}index_7\\.off: OFF: line 6: face 0: vertex index '7' out of range \\[0, 2\\]"
  ${_ss_cli} render "${_bm}/index_7_off.json")
ss_cli_error(mesh.off_huge_count "${_mesh}huge_count\\.off: OFF: the header declares 2000000000 vertices and 1 faces"
  ${_ss_cli} render "${_bm}/huge_count_off.json")
ss_cli_error(mesh.off_negative_count "${_mesh}negative_count\\.off: OFF: line 2: vertex count '-5' is not an integer"
  ${_ss_cli} render "${_bm}/negative_count_off.json")
ss_cli_error(mesh.stl_short "${_mesh}short\\.stl: STL: binary STL header declares 1000000 triangles .* but the file has 584 bytes"
  ${_ss_cli} render "${_bm}/short_stl.json")
# a degenerate OFF face: drop-and-warn (the picture is rendered, exit code 0)
add_test(NAME cli.render.off_repeated_vertex
  COMMAND sh -c "env -u DISPLAY \"$0\" render \"$1\" --size 64x48 --frames 1 2>&1 && echo EXIT0"
    ${_ss_cli} "${_bm}/repeated_vertex_off.json")
set_tests_properties(cli.render.off_repeated_vertex PROPERTIES LABELS "cli" TIMEOUT 120
  PASS_REGULAR_EXPRESSION "objects\\[0\\]\\.mesh: [^ ]*repeated_vertex\\.off: OpenMesh kept 1 of the 2 faces.*EXIT0")
ss_cli_error(compare.pfm_scale_zero "cannot read '[^']*scale0\\.pfm': PFM scale '0' is not a finite non-zero number"
  ${_ss_cli} compare "${_bm}/scale0.pfm" "${_bm}/good.pfm")
ss_cli_error(compare.pfm_huge_header "cannot read '[^']*huge\\.pfm': PFM size '2000000000' x '2000000000' is not two integers in \\[1, 65536\\]"
  ${_ss_cli} compare "${_bm}/good.pfm" "${_bm}/huge.pfm")
add_test(NAME cli.compare.good_pfm COMMAND ${_ss_cli} compare "${_bm}/good.pfm" "${_bm}/good.pfm")
set_tests_properties(cli.compare.good_pfm PROPERTIES LABELS "cli" PASS_REGULAR_EXPRESSION "\"mae\": 0")
# A full device: every writer fails with the path and the reason (issue 17).
if (EXISTS /dev/full)
  set(_full "cannot write '/dev/full': No space left on device")
  set(_small "${PROJECT_SOURCE_DIR}/Data/Scenes/demo.json" --size 64x48 --frames 1)

  ss_cli_error(write.stats_full "${_full}" env -u DISPLAY ${_ss_cli} render ${_small} --stats /dev/full)
  # image paths on the full device: links to it (the format is by extension)
  foreach (ext png pfm exr)
    file(CREATE_LINK /dev/full "${_ss_out}/full.${ext}" SYMBOLIC)
  endforeach ()
  ss_cli_error(write.png_full "cannot write '[^']*full\\.png': No space left on device"
    env -u DISPLAY ${_ss_cli} render ${_small} --output "${_ss_out}/full.png")
  ss_cli_error(write.pfm_full "cannot write '[^']*full\\.pfm': No space left on device"
    env -u DISPLAY ${_ss_cli} render ${_small} --method pcss --visibility "${_ss_out}/full.pfm")
  ss_cli_error(write.exr_full "cannot write '[^']*full\\.exr': No space left on device"
    env -u DISPLAY ${_ss_cli} render ${_small} --method pcss --positions "${_ss_out}/full.exr")
endif ()

set(_demo "${PROJECT_SOURCE_DIR}/Data/Scenes/demo.json")
ss_cli_error(unknown_method "--method: unknown method 'fancy'" ${_ss_cli} render "${_demo}" --method fancy)
ss_cli_error(gears_samples "--option gears_samples: expected an integer in \\[1, 32\\]" ${_ss_cli} render "${_demo}" --method gears --option gears_samples=64)
ss_cli_error(gears_raster "--option gears_raster: expected edge or lut" ${_ss_cli} render "${_demo}" --method gears --option gears_raster=fast)
ss_cli_error(gears_backend "--option gears_backend: expected cpu or gl" ${_ss_cli} render "${_demo}" --method gears --option gears_backend=cuda)
ss_cli_error(gears_report_from "bench --gears --report-from: cannot read /nonexistent/run.json" ${_ss_cli} bench --gears --report-from /nonexistent/run.json --out "${_ss_out}/gears_report_from")
ss_cli_error(gears_report_from_not_a_result "bench --gears --report-from: .*demo.json is not a bench --gears result" ${_ss_cli} bench --gears --report-from "${_demo}" --out "${_ss_out}/gears_report_from")
ss_cli_error(pvsm_metric "--option pvsm_metric: expected auto, dynamic or static" ${_ss_cli} render "${_demo}" --method pvsm --option pvsm_metric=fast)
ss_cli_error(pvsm_quality "--option pvsm_quality: expected a value in \\[0.05, 64\\]" ${_ss_cli} render "${_demo}" --method pvsm --option pvsm_quality=0)
ss_cli_error(pvsm_tile_culling "--option pvsm_tile_culling: expected an integer in \\[0, 1\\]" ${_ss_cli} render "${_demo}" --method pvsm --option pvsm_tile_culling=yes)
ss_cli_error(average_samples "--option average_samples: expected an integer in \\[1, 32\\]" ${_ss_cli} render "${_demo}" --method hardavg --option average_samples=0)
ss_cli_error(bad_size "--size: expected WxH" ${_ss_cli} render "${_demo}" --size 640by480)
ss_cli_error(light_out_of_range "--light 3: out of range" ${_ss_cli} render "${_demo}" --size 64x48 --light 3)
ss_cli_error(unknown_option "--option: unknown key 'sharpness'" ${_ss_cli} render "${_demo}" --option sharpness=3)
ss_cli_error(vtk_visibility "--method vtk: --visibility and --positions are not available" ${_ss_cli} render "${_demo}" --method vtk --visibility "${_ss_out}/x.pfm")
ss_cli_error(unknown_command "unknown command 'draw'" ${_ss_cli} draw "${_demo}")
ss_cli_error(zero_size "--size width: expected an integer" ${_ss_cli} render "${_demo}" --size 0x10)
ss_cli_error(zero_frames "--frames: expected an integer in \\[1, " ${_ss_cli} render "${_demo}" --frames 0)
ss_cli_error(option_bad_value "--option shadow_map_size: expected an integer" ${_ss_cli} render "${_demo}" --option shadow_map_size=big)
ss_cli_error(missing_value "--output: missing value" ${_ss_cli} render "${_demo}" --output)
add_test(NAME cli.help COMMAND ${_ss_cli} --help)
# every --option key, from the one table ApplyOption uses (issue 24: --help had
# omitted pvsm_tile_culling); the solvers' keys from the registry (issue 19;
# python.SolverOptions checks every one)
set_tests_properties(cli.help PROPERTIES LABELS "cli" PASS_REGULAR_EXPRESSION
  "usage:.*softshadows render SCENE\\.json.*frame_budget.*each method's own.*pvsm_tile_culling \\(0\\|1\\).*average_samples \\(1\\.\\.32\\).*default 8\\]")

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
# a volume object read from a .vti (its "density" array, a transform): the
# planner gives its light vpcss, which shadows the ground through it (issue 20)
ss_cli_render(volume_file "${_ss_data}/GoodScenes/volume_file.json" soft --size 320x240)
# the translucent receivers' scene of vpcss.md: a sheet that casts nothing under a
# translucent layer; the planner gives the light vpcss for the layer
add_test(NAME cli.render.translucent_sheet
  COMMAND env -u DISPLAY ${_ss_cli} render "${PROJECT_SOURCE_DIR}/Data/Scenes/translucent_sheet.json" --size 160x120
    --output "${_ss_out}/cli_translucent_sheet.png")
set_tests_properties(cli.render.translucent_sheet PROPERTIES LABELS "cli" TIMEOUT 300
  PASS_REGULAR_EXPRESSION "light 0: vpcss - area light with translucent casters")
# A scene with a mesh file (.off through OpenMesh; the mesh is committed, not
# generated). Run through the test wrapper, so the program takes the path
# where DISPLAY is already set (the wrapper's Xvfb, or the developer's X).
set(_p "${_ss_out}/cli_torus")
add_test(NAME cli.render.torus_off
  COMMAND "${SOFTSHADOWS_HEADLESS}" ${_ss_cli} render "${PROJECT_SOURCE_DIR}/Data/Scenes/torus.json"
    --method pcss --output "${_p}.png" --visibility "${_p}_v.pfm" --positions "${_p}_p.pfm"
    --stats "${_p}.json")
add_test(NAME cli.check.torus_off COMMAND ssCheckOutputs "${_p}.json" "${_p}_v.pfm" "${_p}_p.pfm" soft)
set_tests_properties(cli.render.torus_off PROPERTIES LABELS "cli" TIMEOUT 300 FIXTURES_SETUP cli_torus)
set_tests_properties(cli.check.torus_off PROPERTIES LABELS "cli" FIXTURES_REQUIRED cli_torus)

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
add_test(NAME cli.bench.vpcss_smoke
  COMMAND env -u DISPLAY ${_ss_cli} bench --vpcss --smoke --scenes "${PROJECT_SOURCE_DIR}/Data/Scenes/translucent.json,${PROJECT_SOURCE_DIR}/Data/Scenes/volume.json"
    --size 160x120 --frames 1 --reference-samples 4 --out "${_ss_out}/bench_vpcss_smoke")
add_test(NAME cli.bench.vpcss_smoke_check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_vpcss_bench.py" "${_ss_out}/bench_vpcss_smoke")
set_tests_properties(cli.bench.vpcss_smoke PROPERTIES LABELS "cli;bench" TIMEOUT 300 FIXTURES_SETUP bench_vpcss_smoke)
set_tests_properties(cli.bench.vpcss_smoke_check PROPERTIES LABELS "cli;bench" FIXTURES_REQUIRED bench_vpcss_smoke)
add_test(NAME cli.bench.gears_smoke
  COMMAND env -u DISPLAY ${_ss_cli} bench --gears --smoke --scenes "${PROJECT_SOURCE_DIR}/Data/Scenes/sphere_plane.json"
    --sizes 160x120 --samples 8 --frames 1 --out "${_ss_out}/bench_gears_smoke")
add_test(NAME cli.bench.gears_smoke_check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_gears_bench.py" "${_ss_out}/bench_gears_smoke")
set_tests_properties(cli.bench.gears_smoke PROPERTIES LABELS "cli;bench" TIMEOUT 300 FIXTURES_SETUP bench_gears_smoke)
set_tests_properties(cli.bench.gears_smoke_check PROPERTIES LABELS "cli;bench" FIXTURES_REQUIRED bench_gears_smoke)
# --report-from: the smoke run's rows given twice make one report of both runs
add_test(NAME cli.bench.gears_report_from
  COMMAND ${_ss_cli} bench --gears --report-from "${_ss_out}/bench_gears_smoke/gears-bench.json,${_ss_out}/bench_gears_smoke/gears-bench.json"
    --out "${_ss_out}/bench_gears_report_from")
add_test(NAME cli.bench.gears_report_from_check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_gears_bench.py" "${_ss_out}/bench_gears_report_from" 2)
set_tests_properties(cli.bench.gears_report_from PROPERTIES LABELS "cli;bench" PASS_REGULAR_EXPRESSION "from 2 runs"
  FIXTURES_REQUIRED bench_gears_smoke FIXTURES_SETUP bench_gears_report_from)
set_tests_properties(cli.bench.gears_report_from_check PROPERTIES LABELS "cli;bench" FIXTURES_REQUIRED bench_gears_report_from)
# the silhouette winding raster's probe: identical to the triangle raster where it applies
add_test(NAME cli.bench.gears_silhouette_probe
  COMMAND env -u DISPLAY ${_ss_cli} bench --gears --scenes "${PROJECT_SOURCE_DIR}/Data/Scenes/torus.json"
    --sizes 160x120 --samples 8,16 --silhouette-probe 7 --out "${_ss_out}/bench_gears_silhouette_probe")
add_test(NAME cli.bench.gears_silhouette_probe_check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_gears_silhouette_probe.py"
    "${_ss_out}/bench_gears_silhouette_probe")
set_tests_properties(cli.bench.gears_silhouette_probe PROPERTIES LABELS "cli;bench" TIMEOUT 300
  FIXTURES_SETUP bench_gears_silhouette_probe)
set_tests_properties(cli.bench.gears_silhouette_probe_check PROPERTIES LABELS "cli;bench"
  FIXTURES_REQUIRED bench_gears_silhouette_probe)
add_test(NAME cli.bench.pvsm_smoke
  COMMAND env -u DISPLAY ${_ss_cli} bench --pvsm --smoke --scenes "${PROJECT_SOURCE_DIR}/Data/Scenes/sphere_plane.json"
    --size 160x120 --frames 1 --reference-samples 4 --out "${_ss_out}/bench_pvsm_smoke")
add_test(NAME cli.bench.pvsm_smoke_check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_pvsm_bench.py" "${_ss_out}/bench_pvsm_smoke" 4)
set_tests_properties(cli.bench.pvsm_smoke PROPERTIES LABELS "cli;bench" TIMEOUT 300 FIXTURES_SETUP bench_pvsm_smoke)
set_tests_properties(cli.bench.pvsm_smoke_check PROPERTIES LABELS "cli;bench" FIXTURES_REQUIRED bench_pvsm_smoke)

# bake and prepare (the Filters module; no GPU, no display needed)
set(_good "${_ss_data}/GoodScenes")
file(WRITE "${_gen}/no_lights.json" "{\"objects\": [{\"primitive\": \"sphere\"}]}\n")
ss_cli_error(bake_missing_object "bake: missing --object" ${_ss_cli} bake "${_good}/bake_plane.json" --output "${_ss_out}/x.vtp")
ss_cli_error(bake_missing_output "bake: missing --output" ${_ss_cli} bake "${_good}/bake_plane.json" --object 0)
ss_cli_error(bake_object_range "--object 7: out of range \\(the scene has 2 object" ${_ss_cli} bake "${_good}/bake_plane.json" --object 7 --output "${_ss_out}/x.vtp")
ss_cli_error(bake_method "--method: expected gears or reference, got 'pcss'" ${_ss_cli} bake "${_good}/bake_plane.json" --object 0 --output "${_ss_out}/x.vtp" --method pcss)
ss_cli_error(bake_samples "--samples: expected an integer in \\[1, 32\\]" ${_ss_cli} bake "${_good}/bake_plane.json" --object 0 --output "${_ss_out}/x.vtp" --samples 64)
ss_cli_error(bake_missing_scene "nope\\.json: cannot open" ${_ss_cli} bake "${_bad}/nope.json" --object 0 --output "${_ss_out}/x.vtp")
ss_cli_error(bake_bad_scene "unknown_key\\.json: objects\\[0\\]\\.radious: unknown key" ${_ss_cli} bake "${_bad}/unknown_key.json" --object 0 --output "${_ss_out}/x.vtp")
ss_cli_error(bake_no_lights "no_lights\\.json: lights: the scene has no light" ${_ss_cli} bake "${_gen}/no_lights.json" --object 0 --output "${_ss_out}/x.vtp")
ss_cli_error(bake_unwritable "cannot write '/nonexistent/dir/x\\.vtp'" ${_ss_cli} bake "${_good}/bake_plane.json" --object 1 --output /nonexistent/dir/x.vtp)
ss_cli_error(prepare_missing_mesh "nope\\.off: mesh: mesh file not found" ${_ss_cli} prepare "${_bad}/nope.off" --output "${_ss_out}/x.vtp")
ss_cli_error(prepare_not_a_mesh "empty\\.vtp: mesh: could not read" ${_ss_cli} prepare "${_gen}/empty.vtp" --output "${_ss_out}/x.vtp")
ss_cli_error(prepare_missing_output "prepare: missing --output" ${_ss_cli} prepare "${_good}/nan_and_degenerate.ply")
ss_cli_error(prepare_tolerance "--tolerance: expected a fraction of the bounding-box diagonal in \\[0, 0.01\\], got '0.5'" ${_ss_cli} prepare "${_good}/nan_and_degenerate.ply" --output "${_ss_out}/x.vtp" --tolerance 0.5)
ss_cli_error(prepare_boxes "--boxes: expected plane, optimal or aligned, got 'round'" ${_ss_cli} prepare "${_good}/nan_and_degenerate.ply" --output "${_ss_out}/x.vtp" --boxes round)
# Found by a bad-input sweep (stop 35): objects[i] counts volumes too; a disk
# is wound as its normal says; outputs are .vtp and no input; a mesh the weld
# merges away is an error, not an empty file.
ss_cli_error(bake_volume_object "volume\\.json: objects\\[1\\]: a volume; bake writes" ${_ss_cli} bake "${PROJECT_SOURCE_DIR}/Data/Scenes/volume.json" --object 1 --output "${_ss_out}/x.vtp")
add_test(NAME cli.bake.object_after_volume
  COMMAND ${_ss_cli} bake "${PROJECT_SOURCE_DIR}/Data/Scenes/volume.json" --object 2 --output "${_ss_out}/after_volume.vtp" --samples 2)
set_tests_properties(cli.bake.object_after_volume PROPERTIES LABELS "cli;filters" TIMEOUT 120
  PASS_REGULAR_EXPRESSION "objects\\[1\\] is a volume; bake does not cast volumes.*baked object 2 \\(24 points\\)")
add_test(NAME cli.bake.disk_facing_the_light
  COMMAND ${_ss_cli} bake "${PROJECT_SOURCE_DIR}/Data/Scenes/demo.json" --object 4 --output "${_ss_out}/bake_disk.vtp" --samples 8)
add_test(NAME cli.bake.disk_facing_the_light_check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_bake_mean.py" "${_ss_out}/bake_disk.vtp" LightVisibility_0 0.95 1.0)
set_tests_properties(cli.bake.disk_facing_the_light PROPERTIES LABELS "cli;filters" TIMEOUT 120 FIXTURES_SETUP bake_disk)
set_tests_properties(cli.bake.disk_facing_the_light_check PROPERTIES LABELS "cli;filters" FIXTURES_REQUIRED bake_disk)
ss_cli_error(bake_output_extension "--output: expected a \\.vtp file" ${_ss_cli} bake "${_good}/bake_plane.json" --object 0 --output "${_ss_out}/x.vtk")
file(COPY "${_good}/bake_plane.json" DESTINATION "${_gen}/bake_self")
ss_cli_error(bake_output_is_scene "--output: expected a \\.vtp file" ${_ss_cli} bake "${_gen}/bake_self/bake_plane.json" --object 0 --output "${_gen}/bake_self/bake_plane.json")
ss_cli_error(prepare_report_is_output "--output '.*same\\.vtp' is also" ${_ss_cli} prepare "${PROJECT_SOURCE_DIR}/Data/Meshes/torus.off" --output "${_ss_out}/same.vtp" --report "${_ss_out}/same.vtp")
file(WRITE "${_gen}/welded_away.off" "OFF\n6 2 0\n0 0 0\n1e-7 0 0\n0 1e-7 0\n1e6 0 0\n1e6 1 0\n1e6 0 1\n3 0 1 2\n3 3 4 5\n")
# (after the progress lines: an error, exit 2, and no file)
add_test(NAME cli.error.prepare_welded_away
  COMMAND sh -c "rm -f \"$1\"; \"$0\" prepare \"$2\" --output \"$1\"; rc=$?; test $rc -eq 2 && test ! -e \"$1\" && echo exit-2-no-file"
    ${_ss_cli} "${_ss_out}/welded_away.vtp" "${_gen}/welded_away.off")
set_tests_properties(cli.error.prepare_welded_away PROPERTIES LABELS "cli" TIMEOUT 60
  PASS_REGULAR_EXPRESSION "softshadows: error: prepare: .*welded_away\\.off: no triangle is left of 2 \\(2 collapsed by the weld.*exit-2-no-file")
# Faces of 1-2 vertices in PLY and OFF: the error says they may be why the
# data is shorter than the header asks (it blamed a cut alone before stop 53).
file(WRITE "${_gen}/short_faces.ply" "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n1 0\n")
file(WRITE "${_gen}/short_faces.off" "OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n1 0\n")
foreach (_ext ply off)
  string(TOUPPER ${_ext} _fmt)
  ss_cli_error(prepare_short_faces_${_ext} "short_faces\\.${_ext}: .*${_fmt}: the header declares 3 vertices and 3 faces .* the file is cut short, or its faces have fewer than 3 vertices"
    ${_ss_cli} prepare "${_gen}/short_faces.${_ext}" --output "${_ss_out}/x.vtp")
endforeach ()
ss_cli_error(bench_filters_no_mesh "bench --filters: missing --mesh" ${_ss_cli} bench --filters)

# A broken mesh (a NaN vertex, a collapsed triangle): the report counts them.
# A write that fails part-way (a full disk; here a file-size limit) leaves no
# half-written file behind, for prepare, bake and render's pictures alike
# (before stop 53 the first 4-16 KiB of a .vtp or .png stayed, next to an
# exit code 2).
foreach (cmd IN ITEMS prepare bake render)
  if (cmd STREQUAL "render")
    set(_ss_args "render \"$2\" --method hard --output \"$1\"")
    set(_ss_in "${PROJECT_SOURCE_DIR}/Data/Scenes/demo.json")
  elseif (cmd STREQUAL "prepare")
    set(_ss_args "prepare \"$2\" --output \"$1\"")
    set(_ss_in "${PROJECT_SOURCE_DIR}/Data/Meshes/torus.off")
  else ()
    set(_ss_args "bake \"$2\" --object 1 --samples 2 --output \"$1\"")
    set(_ss_in "${PROJECT_SOURCE_DIR}/Data/Scenes/demo.json")
  endif ()
  set(_ss_ext vtp)
  set(_ss_wrap "")
  if (cmd STREQUAL "render")
    # the display from headless.sh, outside the limit: a private Xvfb the
    # program starts itself would inherit it and fail to start
    set(_ss_ext png)
    set(_ss_wrap "${PROJECT_SOURCE_DIR}/Testing/headless.sh")
  endif ()
  add_test(NAME cli.error.${cmd}_no_partial_file
    COMMAND ${_ss_wrap} sh -c "trap '' XFSZ; ulimit -f 4; rm -f \"$1\"; \"$0\" ${_ss_args}; rc=$?; test $rc -eq 2 && test ! -e \"$1\" && echo exit-2-no-file"
      ${_ss_cli} "${_ss_out}/partial_${cmd}.${_ss_ext}" "${_ss_in}")
  set_tests_properties(cli.error.${cmd}_no_partial_file PROPERTIES LABELS "cli" TIMEOUT 120
    PASS_REGULAR_EXPRESSION "cannot write '.*partial_${cmd}\\.${_ss_ext}'.*exit-2-no-file")
endforeach ()
add_test(NAME cli.prepare.broken_mesh
  COMMAND ${_ss_cli} prepare "${_good}/nan_and_degenerate.ply" --output "${_ss_out}/cli_prepared.vtp"
    --report "${_ss_out}/cli_prepared.json")
set_tests_properties(cli.prepare.broken_mesh PROPERTIES LABELS "cli;filters" TIMEOUT 120
  PASS_REGULAR_EXPRESSION "NonFinitePoints: 1\n.*CollapsedTriangles: 1\n.*OutputTriangles: 2\n")
# Bake a transformed plane under a sphere with GEARS and the reference; the
# check reads both files back (world coordinates, arrays, agreement).
foreach (_m gears reference)
  add_test(NAME cli.bake.${_m}
    COMMAND env -u DISPLAY ${_ss_cli} bake "${_good}/bake_plane.json" --object 0 --samples 8 --method ${_m}
      --output "${_ss_out}/cli_baked_${_m}.vtp")
  set_tests_properties(cli.bake.${_m} PROPERTIES LABELS "cli;filters" TIMEOUT 300 FIXTURES_SETUP cli_bake)
endforeach ()
add_test(NAME cli.bake.check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_bake.py"
    "${_ss_out}/cli_baked_gears.vtp" "${_ss_out}/cli_baked_reference.vtp")
set_tests_properties(cli.bake.check PROPERTIES LABELS "cli;filters" FIXTURES_REQUIRED cli_bake)
# Benchmark smoke run (a small sphere, a 10k-point plane): the report is produced.
add_test(NAME cli.bench.filters_smoke
  COMMAND ${_ss_cli} bench --filters --smoke --out "${_ss_out}/bench_filters_smoke")
set_tests_properties(cli.bench.filters_smoke PROPERTIES LABELS "cli;bench;filters" TIMEOUT 300
  PASS_REGULAR_EXPRESSION "prepare [0-9.e+-]+ s per million triangles")
add_test(NAME cli.bench.culling_smoke
  COMMAND ${_ss_cli} bench --culling --smoke --frames 1 --out "${_ss_out}/bench_culling_smoke")
set_tests_properties(cli.bench.culling_smoke PROPERTIES LABELS "cli;bench;filters" TIMEOUT 300
  PASS_REGULAR_EXPRESSION "close-up / gears, prepared \\(closed pieces\\): [0-9.e+-]+ ms")

# Other machines' paths on this one (issue 16): llvmpipe thread counts, a
# smaller GL texture limit, a GL 3.2 context, a small SSBO limit, Embree's
# AVX2 and SSE4.2 kernels. Each must give the same V or a stated fallback.
add_test(NAME cli.machine.paths
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_machine_paths.py" ${_ss_cli} "${_demo}"
    "${_ss_out}/machine_paths")
set_tests_properties(cli.machine.paths PROPERTIES LABELS "cli" TIMEOUT 600)

# Issue 17: an inline vertex beyond the float range is dropped with a warning
# and the other casters still cast.
add_test(NAME cli.render.float_overflow_vertex
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_float_overflow.py" ${_ss_cli}
    "${_ss_data}/GoodScenes/float_overflow.json" "${_ss_out}/float_overflow")
set_tests_properties(cli.render.float_overflow_vertex PROPERTIES LABELS "cli" TIMEOUT 120)
# Pairs of scenes that must render the same frame (check_same_frames.py):
# cli.render.NAME compares SCENE_A with SCENE_B under METHODS (a comma list;
# all ten when not given).
function (ss_same_frames_test name scene_a scene_b)
  set(methods "hard,pcf,pcss,pvsm,hardavg,asm,vpcss,avsm,gears,reference")
  if (ARGC GREATER 3)
    set(methods "${ARGV3}")
  endif ()
  add_test(NAME cli.render.${name}
    COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_same_frames.py" ${_ss_cli}
      "${_ss_data}/GoodScenes/${scene_a}" "${_ss_data}/GoodScenes/${scene_b}" "${_ss_out}/${name}" "${methods}")
  set_tests_properties(cli.render.${name} PROPERTIES LABELS "cli" TIMEOUT 300)
endfunction ()
# A scene 2e6 units from the origin renders as the same scene at the origin
# (the primitives' points are double).
ss_same_frames_test(far_from_origin far_origin_reference.json far_from_origin.json "hard,pcss,pvsm,gears,reference")
# The same scene in units 1e12 times larger renders the same frame (stop 45:
# the G-buffer's facet normal overflowed float there, came out 0, and ASM's
# picture was black; the reference, in Embree's units, lost shadow at 1e14).
ss_same_frames_test(scale_1e12 scale_1.json scale_1e12.json "hard,pcss,asm,gears,reference")
# --output takes the picture of the last measured frame and changes nothing
# that --visibility reports (before, one more render gave both).
add_test(NAME cli.render.output_same_frame
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_output_same_frame.py" ${_ss_cli}
    "${PROJECT_SOURCE_DIR}/Data/Scenes/canopy.json" "${_ss_out}/output_same_frame")
set_tests_properties(cli.render.output_same_frame PROPERTIES LABELS "cli" TIMEOUT 300)
# Without shadow work (no shadow-casting object, no light) --visibility gives
# V = 1 on the surfaces, the same pixels as with a caster out of view (before:
# all NaN, the pass keeping no positions then).
add_test(NAME cli.render.no_shadow_work
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_no_shadow_work.py" ${_ss_cli}
    "${_ss_out}/no_shadow_work")
set_tests_properties(cli.render.no_shadow_work PROPERTIES LABELS "cli" TIMEOUT 300)
# Maps at the top of their ranges (PVSM's tiles, the whole-view shadow maps)
# render: an array the context cannot hold is halved until it can.
add_test(NAME cli.render.large_maps
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_large_maps.py" ${_ss_cli}
    "${PROJECT_SOURCE_DIR}/Data/Scenes/demo.json" "${_ss_out}/large_maps")
set_tests_properties(cli.render.large_maps PROPERTIES LABELS "cli" TIMEOUT 300)
# One stray triangle 4e5 units away, out of view, changes nothing in the
# frame under any method (the clipping range, the float origin, the start
# offset and the search depth come from what is seen and the casters' bulk).
ss_same_frames_test(stray_triangle stray_reference.json stray_triangle.json)
# A receiver sliver in view reaching 1e10 (below the plane, hidden by it):
# before stop 49 its bounds set the far plane and the near plane followed to
# 1/1000 of it, and the picture was empty under every method; until stop 50
# ASM lost its shadows (its views' depth floor and fixed-point depth range
# from the receivers' whole bounds).
ss_same_frames_test(far_sliver_in_view stray_reference.json far_sliver_in_view.json)
# Two casting needles from under the plane to 1e10 (one down, one sideways;
# hidden by the plane): before stop 50 they belonged to the casters' bulk by
# their size, so the float origin went 5e9 out and the start offset to 1e5:
# GEARS and the reference V = 0 everywhere, the map methods without shadows.
ss_same_frames_test(far_needles_casting stray_reference.json far_needles_casting.json)
# A thin caster far out (1e6 to 2e6) beside the scene: the same frame (and
# GEARS' GL backend too). Before stop 53 it counted in the casters' bulk (near
# it by its own length), the start offset grew to 28 units, past the light:
# GEARS and the reference V = 0 on every pixel (Core:
# Reference.ASliverToAFarVertexChangesNoShadowNearTheScene).
ss_same_frames_test(far_sliver_apart stray_reference.json far_sliver_apart.json
  "hard,pcss,pvsm,asm,vpcss,gears,gears@gears_backend=gl,reference")
# A casting strip in view from the plane to 1e4 or to 1e10 (past the light,
# out of the frame's top): the same frame. Before stop 50, at 1e10 VTK's
# automatic shift of the strip's coordinates to its bounds' centre (5e9) left
# its bottom on a 512-unit grid, so the strip vanished from the picture.
ss_same_frames_test(needle_to_sky needle_to_sky_near.json needle_to_sky_far.json)
# The same four pairs with PVSM's conservative map forced onto the CPU
# (pvsm_map_raster=cpu; auto gives these small scenes the geometry shader).
# The first CPU map lost the needles' scene its shadows (a needle behind the
# light drawn as a box at depth ~0).
foreach (pair IN ITEMS "stray_triangle;stray_reference.json;stray_triangle.json"
    "far_sliver_in_view;stray_reference.json;far_sliver_in_view.json"
    "far_needles_casting;stray_reference.json;far_needles_casting.json"
    "needle_to_sky;needle_to_sky_near.json;needle_to_sky_far.json")
  list(GET pair 0 _ss_pair_name)
  list(GET pair 1 _ss_pair_a)
  list(GET pair 2 _ss_pair_b)
  ss_same_frames_test(${_ss_pair_name}_cpu_map ${_ss_pair_a} ${_ss_pair_b} "pvsm@pvsm_map_raster=cpu")
endforeach ()
add_test(NAME cli.bake.stray_triangle_without
  COMMAND ${_ss_cli} bake "${_ss_data}/GoodScenes/stray_reference.json" --object 1 --output "${_ss_out}/bake_stray_ref.vtp")
add_test(NAME cli.bake.stray_triangle_with
  COMMAND ${_ss_cli} bake "${_ss_data}/GoodScenes/stray_triangle.json" --object 1 --output "${_ss_out}/bake_stray.vtp")
add_test(NAME cli.bake.stray_triangle
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_bake_mean.py" "${_ss_out}/bake_stray.vtp"
    LightVisibility_0 --same-as "${_ss_out}/bake_stray_ref.vtp")
set_tests_properties(cli.bake.stray_triangle_without cli.bake.stray_triangle_with PROPERTIES
  LABELS "cli;filters" TIMEOUT 120 FIXTURES_SETUP bake_stray)
set_tests_properties(cli.bake.stray_triangle PROPERTIES LABELS "cli;filters" FIXTURES_REQUIRED bake_stray)
# The same 3:1 rect light, tilted off the scene, at 1e9 and 1e16 (same angular
# size): the bakes must agree. At 1e16 the scene's normal, kept by VTK as
# focal point - position, rounded away (differences up to 0.24 before the
# fix), and GEARS solves both through its far-light map (gears.md).
add_test(NAME cli.bake.far_light_1e9
  COMMAND ${_ss_cli} bake "${_ss_data}/GoodScenes/far_light_1e9.json" --object 0 --output "${_ss_out}/bake_far_1e9.vtp")
add_test(NAME cli.bake.far_light_1e16
  COMMAND ${_ss_cli} bake "${_ss_data}/GoodScenes/far_light_1e16.json" --object 0 --output "${_ss_out}/bake_far_1e16.vtp")
add_test(NAME cli.bake.far_light_same
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_bake_mean.py" "${_ss_out}/bake_far_1e16.vtp"
    LightVisibility_0 --same-as "${_ss_out}/bake_far_1e9.vtp")
set_tests_properties(cli.bake.far_light_1e9 cli.bake.far_light_1e16 PROPERTIES
  LABELS "cli;filters" TIMEOUT 120 FIXTURES_SETUP bake_far)
set_tests_properties(cli.bake.far_light_same PROPERTIES LABELS "cli;filters" FIXTURES_REQUIRED bake_far)
# A light normal of 1e155 (its squared length overflows): the same light as a
# unit normal (before, the normal came out zero: bake refused it, render left
# the light unshadowed).
add_test(NAME cli.bake.huge_normal
  COMMAND ${_ss_cli} bake "${_ss_data}/GoodScenes/huge_normal.json" --object 1 --output "${_ss_out}/bake_huge_normal.vtp")
set_tests_properties(cli.bake.huge_normal PROPERTIES LABELS "cli;filters" TIMEOUT 120 FIXTURES_SETUP bake_huge_normal)
add_test(NAME cli.bake.huge_normal_same
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_bake_mean.py" "${_ss_out}/bake_huge_normal.vtp"
    LightVisibility_0 --same-as "${_ss_out}/bake_stray_ref.vtp")
set_tests_properties(cli.bake.huge_normal_same PROPERTIES LABELS "cli;filters" FIXTURES_REQUIRED "bake_huge_normal;bake_stray")
add_test(NAME cli.bench.asm_smoke
  COMMAND env -u DISPLAY ${_ss_cli} bench --asm --smoke --scenes "${PROJECT_SOURCE_DIR}/Data/Scenes/wires.json"
    --size 160x120 --out "${_ss_out}/bench_asm_smoke")
add_test(NAME cli.bench.asm_smoke_check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_asm_bench.py" "${_ss_out}/bench_asm_smoke" 4)
set_tests_properties(cli.bench.asm_smoke PROPERTIES LABELS "cli;bench" TIMEOUT 300 FIXTURES_SETUP bench_asm_smoke)
set_tests_properties(cli.bench.asm_smoke_check PROPERTIES LABELS "cli;bench" FIXTURES_REQUIRED bench_asm_smoke)
# ASM is progressive: more --frames refine the same still view further
foreach(_n 1 16)
  add_test(NAME cli.render.asm_frames_${_n}
    COMMAND env -u DISPLAY ${_ss_cli} render "${PROJECT_SOURCE_DIR}/Data/Scenes/wires.json" --method asm
      --size 320x240 --frames ${_n} --option asm_time_budget_ms=5 --stats "${_ss_out}/asm_frames_${_n}.json")
  set_tests_properties(cli.render.asm_frames_${_n} PROPERTIES LABELS "cli" TIMEOUT 300 FIXTURES_SETUP asm_frames)
endforeach()
# A picture taken while ASM still refines says so on stderr (stop 45's visual
# review: the 5M assembly leaked light after 1 frame, in silence); a converged
# one does not.
add_test(NAME cli.render.asm_refining_warns
  COMMAND env -u DISPLAY ${_ss_cli} render "${PROJECT_SOURCE_DIR}/Data/Scenes/wires.json" --method asm
    --size 320x240 --frames 1 --option asm_time_budget_ms=5)
set_tests_properties(cli.render.asm_refining_warns PROPERTIES LABELS "cli" TIMEOUT 300
  PASS_REGULAR_EXPRESSION "warning: asm was still refining after 1 frame\\(s\\) \\([0-9]+ node")
add_test(NAME cli.render.asm_converged_quiet
  COMMAND /bin/sh -c "rm -f \"$3\" && out=$(env -u DISPLAY \"$1\" render \"$2\" --method asm --size 320x240 --frames 40 --option asm_time_budget_ms=5 --output \"$3\" --stats \"$3.json\" 2>&1) && test -s \"$3\" && grep -q '\"refining\": false' \"$3.json\" && ! echo \"$out\" | grep -q 'still refining'"
    sh ${_ss_cli} "${PROJECT_SOURCE_DIR}/Data/Scenes/wires.json" "${_ss_out}/asm_converged.png")
set_tests_properties(cli.render.asm_converged_quiet PROPERTIES LABELS "cli" TIMEOUT 600)
add_test(NAME cli.render.asm_frames_check
  COMMAND /usr/bin/python3 "${PROJECT_SOURCE_DIR}/Testing/check_asm_frames.py"
    "${_ss_out}/asm_frames_1.json" "${_ss_out}/asm_frames_16.json")
set_tests_properties(cli.render.asm_frames_check PROPERTIES LABELS "cli" FIXTURES_REQUIRED asm_frames)
