; omnislice 0.1.0 planar 2026-11-30T07:28:29Z
; omnislice:machine {"kind":"cartesian3","axis_limits":{"X":[-110.0,110.0],"Y":[-110.0,110.0],"Z":[0.0,250.0]},"dynamics":{"X":{"velocity":200.0,"acceleration":3000.0,"jerk":100000.0},"Y":{"velocity":200.0,"acceleration":3000.0,"jerk":100000.0},"Z":{"velocity":20.0,"acceleration":500.0,"jerk":10000.0}},"nozzle":{"diameter":0.4,"cone_half_angle_deg":40.0,"cone_length":25.0}}
; omnislice:placement [1,0,0,-3,0,1,0,-3,0,0,1,-0,0,0,0,1]
; omnislice:extrusion {"mode":"absolute","filament_diameter":1.75}
; omnislice:feed {"semantics":"xyz"}
; omnislice:setting layer_height = 0.3
; omnislice:setting line_width = 0.45
; omnislice:setting nozzle_diameter = 0.4
; omnislice:setting filament_diameter = 1.75
; omnislice:setting method = planar
; omnislice:setting machine = cartesian3
; omnislice:setting direction = 0,0,1
; omnislice:setting acceleration = 1500
; omnislice:setting bed_temperature = 60
; omnislice:setting bridge_flow = 80
; omnislice:setting bridge_speed = 20
; omnislice:setting bridge_fan_speed = 100
; omnislice:setting fan_speed = 100
; omnislice:setting first_layer_height = 0.3
; omnislice:setting first_layer_speed = 20
; omnislice:setting fit_mm = 0
; omnislice:setting geodesic.base_band_mm = 0
; omnislice:setting geodesic.interval_mm = 0
; omnislice:setting geodesic.max_thickness_ratio = 0.7
; omnislice:setting geodesic.nozzle_angle_deg = 0
; omnislice:setting geodesic.target_tets = 60000
; omnislice:setting geodesic.tet_size_mm = 0
; omnislice:setting infill = 20
; omnislice:setting infill_angle_deg = 45
; omnislice:setting infill_overlap_pct = 15
; omnislice:setting infill_speed = 70
; omnislice:setting isoplanar.chord_error_mm = 0
; omnislice:setting isoplanar.directions = 180
; omnislice:setting isoplanar.gamma_samples = 36
; omnislice:setting isoplanar.max_feed_mm_s = 0
; omnislice:setting isoplanar.stencil_mm = 1
; omnislice:setting isoplanar.theta_deg = -1
; omnislice:setting junction_deviation = 0.013
; omnislice:setting motion.chord_tolerance = 0.01
; omnislice:setting motion.filter_deg = 10
; omnislice:setting motion.axis_freedom_deg = 15
; omnislice:setting multidir.alpha_max_deg = 45
; omnislice:setting multidir.interface_overlap = 0.8
; omnislice:setting multidir.max_tilt_deg = 0
; omnislice:setting multidir.offset_step_mm = 1
; omnislice:setting multidir.platform_margin_mm = 5
; omnislice:setting multidir.step_angle_deg = 0
; omnislice:setting multidir.w = 10
; omnislice:setting nozzle_temperature = 210
; omnislice:setting outer_wall_speed = 30
; omnislice:setting print_speed = 50
; omnislice:setting retract_inside_max_travel = 10
; omnislice:setting retract_length = 0.8
; omnislice:setting retract_min_travel = 1.5
; omnislice:setting retract_speed = 35
; omnislice:setting rotate_x_deg = 0
; omnislice:setting rotate_y_deg = 0
; omnislice:setting rotate_z_deg = 0
; omnislice:setting scale = 1
; omnislice:setting support.angle_deg = 0
; omnislice:setting support.auto_share_pct = 1
; omnislice:setting support.gap_mm = 0
; omnislice:setting support.lambda = 1e-06
; omnislice:setting support.merge_angle_deg = 30
; omnislice:setting support.min_diameter_mm = 0
; omnislice:setting support.sampling_mm = 0
; omnislice:setting surface.base_mm = 2
; omnislice:setting travel_speed = 150
; omnislice:setting voxel.epsilon = -1
; omnislice:setting voxel.iso_step = 0
; omnislice:setting voxel.layer_mm = 0
; omnislice:setting voxel.max_thickness_ratio = 1.3
; omnislice:setting voxel.max_tilt_deg = 0
; omnislice:setting voxel.max_voxels = 3000000
; omnislice:setting voxel.peel_step = 1
; omnislice:setting voxel.platform_radius_mm = 0
; omnislice:setting voxel.smooth = 20
; omnislice:setting voxel.width_mm = 0
; omnislice:setting bottom_layers = 4
; omnislice:setting fan_off_layers = 1
; omnislice:setting motion.free_rotation_samples = 30
; omnislice:setting multidir.axis_search = 0
; omnislice:setting multidir.beam_width = 8
; omnislice:setting multidir.perturbations = 60
; omnislice:setting multidir.restarts = 3
; omnislice:setting multidir.samples = 250
; omnislice:setting support.roof_layers = 2
; omnislice:setting top_layers = 4
; omnislice:setting walls = 2
; omnislice:setting infill_pattern = grid
; omnislice:setting seam = aligned
; omnislice:setting up = z
; omnislice:setting bridges = true
; omnislice:setting gap_fill = true
; omnislice:setting travel_inside = true
; omnislice:setting center = true
; omnislice:setting bed_size = 220,220,250
; omnislice:setting gcode_flavor = marlin
; omnislice:setting robot_format = csv
; omnislice:setting motion.smooth_orientations = true
; omnislice:setting fill = auto
; omnislice:setting isoplanar.benchmark = true
; omnislice:setting support = auto
; estimated printing time (normal mode) = 26s
; filament used [mm] = 36.10
; filament used [cm3] = 0.09
; omnislice:dialect marlin
G21 ; millimetres
G90 ; absolute positioning
M82 ; absolute extrusion
M140 S60
M104 S210
M190 S60
M109 S210
M107 ; part cooling fan off
G28 ; home
G92 E0
G0 X2.389 Y2.389 Z2.300 F1200
; omnislice:part 0 direction [0,0,1]
; omnislice:layer 0
G0 X2.389 Y2.389 Z0.300
; omnislice:feature wall-inner
;TYPE:WALL-INNER
G1 X-2.389 Y2.389 Z0.300 E0.22984
G1 X-2.389 Y-2.389 Z0.300 E0.45968
G1 X2.389 Y-2.389 Z0.300 E0.68953
G1 X2.389 Y2.389 Z0.300 E0.91937
G0 X2.775 Y2.775 Z0.300 F9000
; omnislice:feature wall-outer
;TYPE:WALL-OUTER
G1 X-2.775 Y2.775 Z0.300 E1.18630 F1200
G1 X-2.775 Y-2.775 Z0.300 E1.45324
G1 X2.775 Y-2.775 Z0.300 E1.72018
G1 X2.775 Y2.775 Z0.300 E1.98711
G0 X2.232 Y1.959 Z0.300 F9000
; omnislice:feature skin
;TYPE:SKIN
G1 X-1.959 Y-2.232 Z0.300 E2.27219 F1200
G0 X-2.232 Y-1.959 Z0.300 F9010.892
G1 X1.959 Y2.232 Z0.300 E2.55726 F1200
G0 X1.414 Y2.232 Z0.300 F9000
G1 X-2.232 Y-1.414 Z0.300 E2.80524 F1200
G0 X-2.232 Y-0.869 Z0.300 F9000
G1 X0.869 Y2.232 Z0.300 E3.01612 F1200
G0 X0.323 Y2.232 Z0.300 F9010.727
G1 X-2.232 Y-0.323 Z0.300 E3.18991 F1200
G0 X-2.232 Y0.222 Z0.300 F9000
G1 X-0.222 Y2.232 Z0.300 E3.32661 F1200
G0 X-0.768 Y2.232 Z0.300 F9010.892
G1 X-2.232 Y0.768 Z0.300 E3.42621 F1200
