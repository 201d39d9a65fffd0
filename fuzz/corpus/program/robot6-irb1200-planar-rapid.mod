MODULE OmnislicePrint
! omnislice 0.1.0 planar 2026-11-30T17:17:18Z
! omnislice:machine {"kind":"robot6","name":"robot6-irb1200","dh":[[0.0,399.1,0.0,-1.5707963267948966],[-1.5707963267948966,0.0,448.0,0.0],[0.0,0.0,42.0,-1.5707963267948966],[0.0,451.0,0.0,1.5707963267948966],[0.0,0.0,0.0,-1.5707963267948966],[3.141592653589793,82.0,0.0,0.0]],"joint_limits":[[-2.9670597283903604,2.9670597283903604],[-1.7453292519943295,2.356194490192345],[-3.490658503988659,1.2217304763960306],[-4.71238898038469,4.71238898038469],[-2.2689280275926285,2.2689280275926285],[-6.981317007977318,6.981317007977318]],"joint_dynamics":[{"velocity":5.026548245743669,"acceleration":20.106192982974676,"jerk":0.0},{"velocity":4.1887902047863905,"acceleration":16.755160819145562,"jerk":0.0},{"velocity":5.183627878423159,"acceleration":20.734511513692635,"jerk":0.0},{"velocity":6.981317007977318,"acceleration":27.925268031909273,"jerk":0.0},{"velocity":7.068583470577034,"acceleration":28.274333882308134,"jerk":0.0},{"velocity":10.471975511965978,"acceleration":41.88790204786391,"jerk":0.0}],"flange_to_platform":[1.0,0.0,0.0,0.0,0.0,1.0,0.0,0.0,0.0,0.0,1.0,50.0,0.0,0.0,0.0,1.0],"nozzle_tip":[600.0,0.0,800.0],"nozzle_axis":[0.0,0.0,1.0],"ik_branches":5,"nozzle":{"diameter":0.4,"cone_half_angle_deg":40.0,"cone_length":25.0}}
! omnislice:placement [1,0,0,-1.5,0,1,0,-1.5,0,0,1,-0,0,0,0,1]
! omnislice:extrusion {"mode":"relative","filament_diameter":1.75}
! omnislice:feed {"semantics":"part_tip"}
! omnislice:setting layer_height = 0.4
! omnislice:setting line_width = 0.45
! omnislice:setting nozzle_diameter = 0.4
! omnislice:setting filament_diameter = 1.75
! omnislice:setting method = planar
! omnislice:setting machine = robot6-irb1200
! omnislice:setting direction = 0,0,1
! omnislice:setting acceleration = 1500
! omnislice:setting bed_temperature = 60
! omnislice:setting bridge_flow = 80
! omnislice:setting bridge_speed = 20
! omnislice:setting bridge_fan_speed = 100
! omnislice:setting fan_speed = 100
! omnislice:setting first_layer_height = 0.4
! omnislice:setting first_layer_speed = 20
! omnislice:setting fit_mm = 0
! omnislice:setting geodesic.base_band_mm = 0
! omnislice:setting geodesic.interval_mm = 0
! omnislice:setting geodesic.max_thickness_ratio = 0.7
! omnislice:setting geodesic.nozzle_angle_deg = 0
! omnislice:setting geodesic.target_tets = 60000
! omnislice:setting geodesic.tet_size_mm = 0
! omnislice:setting infill = 20
! omnislice:setting infill_angle_deg = 45
! omnislice:setting infill_overlap_pct = 15
! omnislice:setting infill_speed = 70
! omnislice:setting isoplanar.chord_error_mm = 0
! omnislice:setting isoplanar.directions = 180
! omnislice:setting isoplanar.gamma_samples = 36
! omnislice:setting isoplanar.max_feed_mm_s = 0
! omnislice:setting isoplanar.stencil_mm = 1
! omnislice:setting isoplanar.theta_deg = -1
! omnislice:setting junction_deviation = 0.013
! omnislice:setting motion.chord_tolerance = 0.01
! omnislice:setting motion.filter_deg = 10
! omnislice:setting motion.axis_freedom_deg = 15
! omnislice:setting multidir.alpha_max_deg = 45
! omnislice:setting multidir.interface_overlap = 0.8
! omnislice:setting multidir.max_tilt_deg = 0
! omnislice:setting multidir.offset_step_mm = 1
! omnislice:setting multidir.platform_margin_mm = 5
! omnislice:setting multidir.step_angle_deg = 0
! omnislice:setting multidir.w = 10
! omnislice:setting nozzle_temperature = 210
! omnislice:setting outer_wall_speed = 30
! omnislice:setting print_speed = 50
! omnislice:setting retract_inside_max_travel = 10
! omnislice:setting retract_length = 0.8
! omnislice:setting retract_min_travel = 1.5
! omnislice:setting retract_speed = 35
! omnislice:setting rotate_x_deg = 0
! omnislice:setting rotate_y_deg = 0
! omnislice:setting rotate_z_deg = 0
! omnislice:setting scale = 1
! omnislice:setting support.angle_deg = 0
! omnislice:setting support.auto_share_pct = 1
! omnislice:setting support.gap_mm = 0
! omnislice:setting support.lambda = 1e-06
! omnislice:setting support.merge_angle_deg = 30
! omnislice:setting support.min_diameter_mm = 0
! omnislice:setting support.sampling_mm = 0
! omnislice:setting surface.base_mm = 2
! omnislice:setting travel_speed = 150
! omnislice:setting voxel.epsilon = -1
! omnislice:setting voxel.iso_step = 0
! omnislice:setting voxel.layer_mm = 0
! omnislice:setting voxel.max_thickness_ratio = 1.3
! omnislice:setting voxel.max_tilt_deg = 0
! omnislice:setting voxel.max_voxels = 3000000
! omnislice:setting voxel.peel_step = 1
! omnislice:setting voxel.platform_radius_mm = 0
! omnislice:setting voxel.smooth = 20
! omnislice:setting voxel.width_mm = 0
! omnislice:setting bottom_layers = 4
! omnislice:setting fan_off_layers = 1
! omnislice:setting motion.free_rotation_samples = 30
! omnislice:setting multidir.axis_search = 0
! omnislice:setting multidir.beam_width = 8
! omnislice:setting multidir.perturbations = 60
! omnislice:setting multidir.restarts = 3
! omnislice:setting multidir.samples = 250
! omnislice:setting support.roof_layers = 2
! omnislice:setting top_layers = 4
! omnislice:setting walls = 2
! omnislice:setting infill_pattern = grid
! omnislice:setting seam = aligned
! omnislice:setting up = z
! omnislice:setting bridges = true
! omnislice:setting gap_fill = true
! omnislice:setting travel_inside = true
! omnislice:setting center = true
! omnislice:setting bed_size = 220,220,250
! omnislice:setting gcode_flavor = marlin
! omnislice:setting robot_format = rapid
! omnislice:setting motion.smooth_orientations = true
! omnislice:setting fill = auto
! omnislice:setting isoplanar.benchmark = true
! omnislice:setting support = auto
! estimated printing time (normal mode) = 6s
! filament used [mm] = 14.85
! filament used [cm3] = 0.04
! omnislice:extruder {"command":"SetAO","signal":"aoExtruder","per_mm_s":0.1}
! The extruder feed follows analog output aoExtruder: SetAO aoExtruder, v with v = 0.1 per mm/s
! of filament (negative while retracting), set as the next MoveAbsJ starts (RAPID's prefetch may
! set it up to one z0 zone early). Joint angles in degrees, the controller's zero and senses.
  PROC main()
    SetAO aoExtruder, 0;
    MoveAbsJ [[0.086847,22.642009,1.612222,0.000000,-114.254231,179.913153],[9E9,9E9,9E9,9E9,9E9,9E9]], v200, fine, tool0;
    ! omnislice:part 0 direction [0,0,1]
    ! omnislice:layer 0
    MoveAbsJ [[0.086847,22.559327,1.460833,0.000000,-114.020160,179.913153],[9E9,9E9,9E9,9E9,9E9,9E9]], v1000\T:=0.0133333333, z0, tool0;
    ! omnislice:feature wall-inner
    SetAO aoExtruder, 0.121119863;
    MoveAbsJ [[0.087111,22.338243,1.770094,0.000000,-114.108336,179.912889],[9E9,9E9,9E9,9E9,9E9,9E9]], v1000\T:=0.091084, z0, tool0;
    MoveAbsJ [[-0.087111,22.338243,1.770094,0.000000,-114.108336,180.087111],[9E9,9E9,9E9,9E9,9E9,9E9]], v1000\T:=0.091084, z0, tool0;
    MoveAbsJ [[-0.086847,22.559327,1.460833,0.000000,-114.020160,180.086847],[9E9,9E9,9E9,9E9,9E9,9E9]], v1000\T:=0.091084, z0, tool0;
    MoveAbsJ [[0.086847,22.559327,1.460833,0.000000,-114.020160,179.913153],[9E9,9E9,9E9,9E9,9E9,9E9]], v1000\T:=0.091084, z0, tool0;
    WaitTime \InPos, 0;
    SetAO aoExtruder, 0;
  ENDPROC
ENDMODULE
