"""ISO 14649-10/-11/-111 entities: attribute order and types as they appear in Part 21.

Inherited attributes come first (Part 21 order). The orders of the entities in the book's
Example 1 are those of research/seed-book-stepnc.md §7.1 (NIST's classes generated from the
2004 EXPRESS); the others follow the same EXPRESS (ISO 14649-10 §4.6-4.8, -11 §4.2-4.3,
-111 §4.3). Types are a small notation checked by :func:`check_value`:

``label`` string · ``real`` number · ``int`` integer · ``bool`` .T./.F. · ``logical``
.T./.F./.U. · ``enum:A|B`` enumeration · ``ref`` any instance · ``ref:GROUP`` an instance
whose entity is in :data:`GROUPS` ``[GROUP]`` (or the entity name itself) · ``list:T`` a
list of T · ``any`` unchecked. A trailing ``?`` marks an OPTIONAL attribute (``$`` allowed).
"""

from __future__ import annotations

from stepnc.part21 import Enum, Ref, Typed

# ----------------------------------------------------------------- shared attribute blocks
_OPERATION = ("its_toolpath:ref:toolpath_list?", "its_tool_direction:ref?")
_MACHINING_OP = _OPERATION + (
    "its_id:label",
    "retract_plane:real?",
    "start_point:ref:point?",
    "its_tool:ref:tool",
    "its_technology:ref:technology",
    "its_machine_functions:ref:machine_functions",
)
_MILLING_OP = _MACHINING_OP + ("overcut_length:real?",)
_MILLING_TYPE_OP = _MILLING_OP + ("approach:ref:approach?", "retract:ref:approach?")
_TWO5D_OP = _MILLING_TYPE_OP + ("its_machining_strategy:ref:two5d_strategy?",)
_PLANE_MILLING = _TWO5D_OP + ("axial_cutting_depth:real?", "allowance_bottom:real?")
_SIDE_MILLING = _TWO5D_OP + (
    "axial_cutting_depth:real?",
    "radial_cutting_depth:real?",
    "allowance_side:real?",
)
_BOTTOM_SIDE = _TWO5D_OP + (
    "axial_cutting_depth:real?",
    "radial_cutting_depth:real?",
    "allowance_side:real?",
    "allowance_bottom:real?",
)
_DRILLING_TYPE = _MILLING_OP + (
    "cutting_depth:real?",
    "previous_diameter:real?",
    "dwell_time_bottom:real?",
    "feed_on_retract:real?",
    "its_machining_strategy:ref:drilling_strategy?",
)
_BORING_OP = _DRILLING_TYPE + (
    "spindle_stop_at_bottom:bool",
    "depth_of_testcut:real?",
    "waiting_position:ref:point?",
)
_FEATURE = ("its_id:label", "its_workpiece:ref:WORKPIECE", "its_operations:list:ref:operation")
_TWO5D_FEATURE = _FEATURE + ("feature_placement:ref:AXIS2_PLACEMENT_3D",)
_MACHINING_FEATURE = _TWO5D_FEATURE + ("depth:ref:surface",)
_POCKET = _MACHINING_FEATURE + (
    "its_boss:list:ref",
    "slope:real?",
    "bottom_condition:ref:pocket_bottom",
    "planar_radius:ref:TOLERANCED_LENGTH_MEASURE?",
    "orthogonal_radius:ref:TOLERANCED_LENGTH_MEASURE?",
)
_MILLING_TOOL_BODY = (
    "dimension:ref:MILLING_TOOL_DIMENSION",
    "number_of_teeth:int?",
    "hand_of_cut:enum:LEFT|RIGHT|NEUTRAL?",
    "coolant_through_tool:bool?",
    "pilot_length:real?",
)
_TOOLPATH = (
    "its_priority:enum:REQUIRED|SUGGESTED|T|F",
    "its_type:enum:TRAJECTORY_PATH|APPROACH|LIFT|CONNECT|NON_CONTACT|CONTACT",
    "its_speed:ref?",
    "its_technology:ref:technology?",
    "its_machine_functions:ref:machine_functions?",
)
_DRIVE_STRATEGY = ("overlap:real?", "allow_multiple_passes:bool?")
_PLUNGE = ("tool_orientation:ref:DIRECTION?",)
# ---- ISO 14649-12 turning and -121 turning tools, in the attribute order of the ARM that
# AP238 ed. 3 carries (stepmfg/ap238 data/ap238e3_arm.exp, "TYPES DEFINED IN PROCESS DATA
# FOR TURNING ISO 14649-12" and "TOOLS FOR TURNING ISO 14649-121"), with the attributes
# AP238 moved to supertypes or inverses put back where the 14649 schema had them.
_TURNING_OP = _MACHINING_OP + (
    "approach:ref?",
    "retract:ref?",
    "its_machining_strategy:ref:turning_strategy?",
)
_TURNING_STRATEGY = (
    "overcut_length:real?",
    "allow_multiple_passes:bool?",
    "cutting_depth:list:real",
    "variable_feedrate:real?",
)
_TURNING_TOOL = (
    "its_id:label",
    "functional_length:real",
    "f_dimension:real",
    "minimum_cutting_diameter:real?",
    "a_dimension_on_f:real?",
    "a_dimension_on_lf:real?",
    "cutting_edge:ref:CUTTING_EDGE_PROPERTIES",
    "hand_of_tool:enum:LEFT|RIGHT|NEUTRAL?",
)
#: revolved features (ISO 14649-12): ``radius`` is a numeric parameter in the standard and
#: a plain number in published examples, so both are read
_REVOLVED = _TWO5D_FEATURE + ("material_side:ref:DIRECTION?", "radius:any")
_NAME = ("name:label",)

#: entity -> attribute specs ``name:type[?]`` in Part 21 order.
ENTITIES: dict[str, tuple[str, ...]] = {
    # ---- Part 10: program structure and executables (§4.6)
    "PROJECT": (
        "its_id:label",
        "main_workplan:ref:WORKPLAN",
        "its_workpieces:list:ref:WORKPIECE",
        "its_owner:ref?",
        "its_release:ref?",
        "its_status:ref?",
    ),
    "WORKPLAN": (
        "its_id:label",
        "its_elements:list:ref:executable",
        "its_channel:ref?",
        "its_setup:ref:SETUP?",
        "its_effect:ref?",
    ),
    "NON_SEQUENTIAL": ("its_id:label", "its_elements:list:ref:executable"),
    "PARALLEL": ("its_id:label", "branches:list:ref:executable"),
    "SELECTIVE": ("its_id:label", "its_elements:list:ref:executable"),
    "IF_STATEMENT": (
        "its_id:label",
        "condition:ref",
        "true_branch:ref:executable",
        "false_branch:ref:executable?",
    ),
    "WHILE_STATEMENT": ("its_id:label", "condition:ref", "body:ref:executable"),
    "MACHINING_WORKINGSTEP": (
        "its_id:label",
        "its_secplane:ref:surface",
        "its_feature:ref:feature",
        "its_operation:ref:operation",
        "its_effect:ref?",
    ),
    "RAPID_MOVEMENT": (
        "its_id:label",
        "its_secplane:ref:surface",
        "its_toolpath:ref:toolpath_list?",
        "its_tool_direction:ref?",
    ),
    "DISPLAY_MESSAGE": ("its_id:label", "its_text:label"),
    "PROGRAM_STOP": ("its_id:label",),
    "OPTIONAL_STOP": ("its_id:label",),
    "LOAD_TOOL": ("its_id:label", "its_tool:ref:tool"),
    "UNLOAD_TOOL": ("its_id:label", "its_tool:ref:tool?"),
    "EXCHANGE_PALLET": ("its_id:label",),
    "SETUP": (
        "its_id:label",
        "its_origin:ref:AXIS2_PLACEMENT_3D?",
        "its_secplane:ref:surface",
        "its_workpiece_setup:list:ref:WORKPIECE_SETUP",
    ),
    "WORKPIECE_SETUP": (
        "its_workpiece:ref:WORKPIECE",
        "its_origin:ref:AXIS2_PLACEMENT_3D",
        "its_offset:ref?",
        "its_restricted_area:ref?",
        "its_instructions:list:ref",
    ),
    "WORKPIECE": (
        "its_id:label",
        "its_material:ref:MATERIAL?",
        "global_tolerance:real?",
        "its_rawpiece:ref:WORKPIECE?",
        "its_geometry:ref?",
        "its_bounding_geometry:ref:bounding?",
        "clamping_positions:list:ref:CARTESIAN_POINT",
    ),
    "MATERIAL": (
        "standard_identifier:label",
        "material_identifier:label",
        "material_property:list:ref",
    ),
    "DESCRIPTIVE_PARAMETER": ("parameter_name:label", "descriptive_string:label"),
    "NUMERIC_PARAMETER": (
        "parameter_name:label",
        "its_parameter_value:real",
        "its_parameter_unit:label",
    ),
    # ---- Part 10 features (§4.7)
    "PLANAR_FACE": _MACHINING_FEATURE
    + (
        "course_of_travel:ref:LINEAR_PATH",
        "removal_boundary:ref:LINEAR_PROFILE",
        "face_boundary:ref:closed_profile?",
        "its_boss:list:ref",
    ),
    "CLOSED_POCKET": _POCKET + ("feature_boundary:ref:closed_profile",),
    "OPEN_POCKET": _POCKET + ("open_boundary:ref:open_profile", "wall_boundary:ref?"),
    "ROUND_HOLE": _MACHINING_FEATURE
    + (
        "diameter:ref:TOLERANCED_LENGTH_MEASURE",
        "change_in_diameter:ref?",
        "bottom_condition:ref:hole_bottom",
    ),
    "SLOT": _MACHINING_FEATURE
    + (
        "course_of_travel:ref:travel_path",
        "swept_shape:ref:open_profile",
        "end_conditions:list:ref",
    ),
    "STEP": _MACHINING_FEATURE + ("open_boundary:ref:LINEAR_PATH", "wall_boundary:ref?"),
    "LINEAR_PATH": (
        "placement:ref:AXIS2_PLACEMENT_3D?",
        "distance:ref:TOLERANCED_LENGTH_MEASURE",
        "its_direction:ref:DIRECTION",
    ),
    "LINEAR_PROFILE": ("placement:ref:AXIS2_PLACEMENT_3D?", "profile_length:ref:numeric"),
    "RECTANGULAR_CLOSED_PROFILE": (
        "placement:ref:AXIS2_PLACEMENT_3D?",
        "profile_width:ref:TOLERANCED_LENGTH_MEASURE",
        "profile_length:ref:TOLERANCED_LENGTH_MEASURE",
    ),
    "CIRCULAR_CLOSED_PROFILE": (
        "placement:ref:AXIS2_PLACEMENT_3D?",
        "diameter:ref:TOLERANCED_LENGTH_MEASURE",
    ),
    "GENERAL_CLOSED_PROFILE": (
        "placement:ref:AXIS2_PLACEMENT_3D?",
        "closed_profile_shape:ref:curve",
    ),
    "GENERAL_PROFILE": ("placement:ref:AXIS2_PLACEMENT_3D?", "its_profile:ref:curve"),
    "SQUARE_U_PROFILE": (
        "placement:ref:AXIS2_PLACEMENT_3D?",
        "width:ref:TOLERANCED_LENGTH_MEASURE",
        "first_radius:ref:TOLERANCED_LENGTH_MEASURE?",
        "first_angle:real?",
        "second_radius:ref:TOLERANCED_LENGTH_MEASURE?",
        "second_angle:real?",
    ),
    "RADIUSED_SLOT_END_TYPE": (),
    "OPEN_SLOT_END_TYPE": (),
    "THROUGH_BOTTOM_CONDITION": (),
    "FLAT_HOLE_BOTTOM": (),
    "FLAT_WITH_RADIUS_HOLE_BOTTOM": ("corner_radius:ref:TOLERANCED_LENGTH_MEASURE",),
    "CONICAL_HOLE_BOTTOM": ("tip_angle:real", "tip_radius:ref:TOLERANCED_LENGTH_MEASURE?"),
    "SPHERICAL_HOLE_BOTTOM": ("radius:ref:TOLERANCED_LENGTH_MEASURE",),
    "PLANAR_POCKET_BOTTOM_CONDITION": (),
    "THROUGH_POCKET_BOTTOM_CONDITION": (),
    "TOLERANCED_LENGTH_MEASURE": ("theoretical_size:real", "implicit_tolerance:ref?"),
    "PLUS_MINUS_VALUE": ("upper_limit:real", "lower_limit:real", "significant_digits:int"),
    # ---- Part 11 operations (§4.2)
    "PLANE_ROUGH_MILLING": _PLANE_MILLING,
    "PLANE_FINISH_MILLING": _PLANE_MILLING,
    "SIDE_ROUGH_MILLING": _SIDE_MILLING,
    "SIDE_FINISH_MILLING": _SIDE_MILLING,
    "BOTTOM_AND_SIDE_ROUGH_MILLING": _BOTTOM_SIDE,
    "BOTTOM_AND_SIDE_FINISH_MILLING": _BOTTOM_SIDE,
    "FREEFORM_OPERATION": _MILLING_TYPE_OP + ("its_machining_strategy:ref?",),
    "DRILLING": _DRILLING_TYPE,
    "CENTER_DRILLING": _DRILLING_TYPE,
    "COUNTER_SINKING": _DRILLING_TYPE,
    "MULTISTEP_DRILLING": _DRILLING_TYPE
    + (
        "retract_distance:real",
        "first_depth:real",
        "depth_of_step:real",
        "dwell_time_step:real?",
    ),
    "REAMING": _BORING_OP,
    "BORING": _BORING_OP,
    "BACK_BORING": _DRILLING_TYPE,
    "TAPPING": _DRILLING_TYPE + ("compensation_chuck:bool",),
    "THREAD_DRILLING": _DRILLING_TYPE + ("helical_movement_on_forward:bool",),
    # ---- strategies (§4.2.8, §4.2.12)
    "UNIDIRECTIONAL_MILLING": _DRIVE_STRATEGY
    + ("feed_direction:ref:DIRECTION?", "cutmode:enum:CLIMB|CONVENTIONAL?"),
    "BIDIRECTIONAL_MILLING": _DRIVE_STRATEGY
    + (
        "feed_direction:ref:DIRECTION?",
        "stepover_direction:enum:LEFT|RIGHT?",
        "its_stroke_connection_strategy:enum:STRAIGHTLINE|LOOP_BACK|DEGOUGE?",
    ),
    "CONTOUR_PARALLEL": _DRIVE_STRATEGY
    + ("rotation_direction:enum:CW|CCW?", "cutmode:enum:CLIMB|CONVENTIONAL?"),
    "CONTOUR_BIDIRECTIONAL": _DRIVE_STRATEGY
    + (
        "feed_direction:ref:DIRECTION?",
        "stepover_direction:enum:LEFT|RIGHT?",
        "rotation_direction:enum:CW|CCW?",
        "spiral_cutmode:enum:CLIMB|CONVENTIONAL?",
    ),
    "CONTOUR_SPIRAL": _DRIVE_STRATEGY
    + ("rotation_direction:enum:CW|CCW?", "cutmode:enum:CLIMB|CONVENTIONAL?"),
    "CENTER_MILLING": _DRIVE_STRATEGY,
    "DRILLING_TYPE_STRATEGY": (
        "reduced_cut_at_start:real?",
        "reduced_feed_at_start:real?",
        "depth_of_start:real?",
        "reduced_cut_at_end:real?",
        "reduced_feed_at_end:real?",
        "depth_of_end:real?",
    ),
    "PLUNGE_TOOLAXIS": _PLUNGE,
    "PLUNGE_RAMP": _PLUNGE + ("angle:real",),
    "PLUNGE_ZIGZAG": _PLUNGE + ("angle:real", "width:real"),
    "PLUNGE_HELIX": _PLUNGE + ("radius:real", "angle:real"),
    # ---- technology and machine functions (§4.2.4, §4.2.5)
    "MILLING_TECHNOLOGY": (
        "feedrate:real?",
        "feedrate_reference:enum:TCP|CCP",
        "cutspeed:real?",
        "spindle:real?",
        "feedrate_per_tooth:real?",
        "synchronize_spindle_with_feed:bool",
        "inhibit_feedrate_override:bool",
        "inhibit_spindle_override:bool",
        "its_adaptive_control:ref?",
    ),
    "MILLING_MACHINE_FUNCTIONS": (
        "coolant:bool",
        "coolant_pressure:real?",
        "mist:bool?",
        "through_spindle_coolant:bool",
        "through_pressure:real?",
        "axis_clamping:list:ref",
        "chip_removal:bool",
        "oriented_spindle_stop:ref?",
        "its_process_model:ref?",
        "other_functions:list:ref",
    ),
    # ---- ISO 14649-12 turning features
    "OUTER_DIAMETER": _TWO5D_FEATURE
    + ("diameter_at_placement:any", "feature_length:any", "reduced_size:ref:taper?"),
    "REVOLVED_FLAT": _REVOLVED + ("flat_edge_shape:ref:LINEAR_PROFILE",),
    "GROOVE": _REVOLVED + ("sweep:ref:open_profile",),
    "GENERAL_REVOLUTION": _REVOLVED + ("outline:ref:open_profile",),
    # ISO 14649-10 taper_select (a round hole's change_in_diameter; an outer diameter's
    # reduced_size)
    "DIAMETER_TAPER": ("final_diameter:any",),
    "ANGLE_TAPER": ("angle:real",),
    "RIGHT_CIRCULAR_CYLINDER": _NAME
    + ("position:ref:AXIS2_PLACEMENT_3D", "height:real", "radius:real"),
    # ---- ISO 14649-12 turning operations, strategies, technology, machine functions
    "FACING_ROUGH": _TURNING_OP + ("allowance:real?",),
    "FACING_FINISH": _TURNING_OP + ("allowance:real?",),
    "CONTOURING_ROUGH": _TURNING_OP + ("allowance:real?",),
    "CONTOURING_FINISH": _TURNING_OP + ("allowance:real?",),
    "GROOVING_ROUGH": _TURNING_OP + ("dwell:any?", "allowance:real?"),
    "GROOVING_FINISH": _TURNING_OP + ("dwell:any?", "allowance:real?"),
    "CUTTING_IN": _TURNING_OP + ("dwell:any?", "allowance:real?"),
    "THREADING_ROUGH": _TURNING_OP + ("allowance:real?",),
    "THREADING_FINISH": _TURNING_OP + ("allowance:real?",),
    "KNURLING": _TURNING_OP,
    "UNIDIRECTIONAL_TURNING": _TURNING_STRATEGY
    + (
        "feed_direction:ref:DIRECTION?",
        "back_path_direction:ref:DIRECTION?",
        "lift_direction:ref:DIRECTION?",
        "stepover_direction:ref:DIRECTION?",
        "lift_height:real?",
        "lift_feed:any?",
        "stepover_feed:any?",
    ),
    "BIDIRECTIONAL_TURNING": _TURNING_STRATEGY
    + ("feed_direction:ref:DIRECTION?", "stepover_direction:ref:DIRECTION?", "stepover_feed:any?"),
    "CONTOUR_TURNING": _TURNING_STRATEGY
    + (
        "feed_direction:ref:DIRECTION?",
        "back_path_direction:ref:DIRECTION?",
        "lift_direction:ref:DIRECTION?",
        "stepover_direction:ref:DIRECTION?",
        "lift_height:real?",
        "lift_feed:any?",
        "stepover_feed:any?",
        "variable_stepover_feed:real?",
    ),
    "THREAD_STRATEGY": _TURNING_STRATEGY
    + (
        "cut_in_amount_function:enum:CONSTANT_DEPTH|VARIABLE_DEPTH|CONSTANT_REMOVAL_AMOUNT",
        "threading_direction:enum:LEFT|RIGHT|CENTER|LEFT_ZIGZAG|RIGHT_ZIGZAG",
        "path_return_angle:real?",
        "lift_height:real?",
    ),
    "GROOVING_STRATEGY": _TURNING_STRATEGY
    + ("grooving_direction:ref:DIRECTION?", "travel_distance:real?"),
    "MULTISTEP_GROOVING_STRATEGY": _TURNING_STRATEGY
    + ("grooving_direction:ref:DIRECTION?", "travel_distance:real?", "retract_distance:real"),
    "EXPLICIT_TURNING_STRATEGY": _TURNING_STRATEGY,
    "TURNING_TECHNOLOGY": (
        "feedrate:real?",
        "feedrate_reference:enum:TCP|CCP",
        "spindle_speed:ref:speed_select",
        "feed_per_revolution:real?",
        "sync_spindle_and_z_feed:bool",
        "inhibit_feedrate_override:bool",
        "inhibit_spindle_override:bool",
        "its_adaptive_control:ref?",
    ),
    "CONST_SPINDLE_SPEED": ("rot_speed:real",),
    "CONST_CUTTING_SPEED": ("speed:real", "max_speed:real?"),
    "TURNING_MACHINE_FUNCTIONS": (
        "coolant:bool",
        "coolant_type:enum:FLOOD|MIST|THROUGH_TOOL?",
        "coolant_pressure:real?",
        "axis_clamping:list:any",
        "chip_removal:bool?",
        "oriented_spindle_stop:ref?",
        "its_process_model:ref?",
        "other_functions:list:ref",
        "tail_stock:bool?",
        "steady_rest:bool?",
        "follow_rest:bool?",
    ),
    # ---- ISO 14649-121 turning tools
    "GENERAL_TURNING_TOOL": _TURNING_TOOL,
    "GROOVING_TOOL": _TURNING_TOOL
    + (
        "cutting_width:real",
        "maximum_grooving_depth:real",
        "corner_radius:real?",
        "maximum_axial_grooving_diameter:real?",
        "minimum_axial_grooving_diameter:real?",
    ),
    "TURNING_THREADING_TOOL": _TURNING_TOOL
    + (
        "threading_pitch:real",
        "thread_hand:enum:LEFT|RIGHT",
        "its_thread_type:enum:INTERNAL|EXTERNAL",
        "thread_profile:enum:FULL_PROFILE|PARTIAL_PROFILE",
        "thread_form_type:label",
    ),
    "KNURLING_TOOL": _TURNING_TOOL
    + (
        "knurl_pattern:enum:STRAIGHT|DIAGONAL|DIAMOND",
        "cutting_length:real?",
        "angle:real?",
        "pitch:real?",
    ),
    "CUTTING_EDGE_PROPERTIES": (
        "its_material:ref?",
        "expected_tool_life:real?",
        "its_technology:ref?",
        "cutting_edge_length:real?",
        "tool_cutting_edge_angle:real?",
        "tool_cutting_edge_angle_type:label?",
        "tool_included_angle:real?",
        "corner_transitions:list:ref:CORNER_TRANSITION",
        "maximum_side_cutting_depth:real?",
        "maximum_end_cutting_depth:real?",
    ),
    "CORNER_TRANSITION": ("corner_identity:int", "transition:ref:corner"),
    "ROUNDED_CORNER": ("corner_radius:real",),
    "CHAMFERED_CORNER": (
        "corner_chamfer_angle:real",
        "corner_chamfer_length:real?",
        "corner_chamfer_width:real?",
    ),
    # ---- Part 111 tools (§4.3)
    "MILLING_CUTTING_TOOL": (
        "its_id:label",
        "its_tool_body:ref:tool_body",
        "its_cutting_edge:list:ref:CUTTING_COMPONENT",
        "overall_assembly_length:real?",
        "direction_for_spindle_orientation:real?",
        "tool_holder_diameter_for_spindle_orientation:real?",
    ),
    "CUTTING_COMPONENT": (
        "tool_offset_length:real",
        "its_material:ref?",
        "technological_data:ref?",
        "expected_tool_life:real?",
        "its_technology:ref?",
    ),
    "MILLING_TOOL_DIMENSION": (
        "diameter:real",
        "tool_top_angle:real?",
        "tool_circumference_angle:real?",
        "cutting_edge_length:real?",
        "edge_radius:real?",
        "edge_center_vertical:real?",
        "edge_center_horizontal:real?",
    ),
    "ENDMILL": _MILLING_TOOL_BODY,
    "TAPERED_ENDMILL": _MILLING_TOOL_BODY + ("taper_angle:real?",),
    "BALL_ENDMILL": _MILLING_TOOL_BODY,
    "FACEMILL": _MILLING_TOOL_BODY,
    "TWIST_DRILL": _MILLING_TOOL_BODY,
    "CENTER_DRILL": _MILLING_TOOL_BODY,
    "COUNTERSINK": _MILLING_TOOL_BODY,
    "REAMER": _MILLING_TOOL_BODY,
    "TAPERED_REAMER": _MILLING_TOOL_BODY + ("taper_angle:real?",),
    "TAP": _MILLING_TOOL_BODY,
    # ---- explicit toolpaths (Part 10 §4.8)
    "TOOLPATH_LIST": ("its_list:list:ref:toolpath",),
    "CUTTER_LOCATION_TRAJECTORY": _TOOLPATH
    + (
        "its_direction:bool?",
        "basiccurve:ref:curve",
        "its_toolaxis:ref:curve?",
        "surface_normal:ref:curve?",
    ),
    "FEEDSTOP": _TOOLPATH + ("dwell:real",),
    # ---- geometry (ISO 10303-42 subset used by ISO 14649)
    "CARTESIAN_POINT": _NAME + ("coordinates:list:real",),
    "DIRECTION": _NAME + ("direction_ratios:list:real",),
    "VECTOR": _NAME + ("orientation:ref:DIRECTION", "magnitude:real"),
    "AXIS2_PLACEMENT_3D": _NAME
    + (
        "location:ref:CARTESIAN_POINT",
        "axis:ref:DIRECTION?",
        "ref_direction:ref:DIRECTION?",
    ),
    "PLANE": _NAME + ("position:ref:AXIS2_PLACEMENT_3D",),
    "ELEMENTARY_SURFACE": _NAME + ("position:ref:AXIS2_PLACEMENT_3D",),
    "BLOCK": _NAME + ("position:ref:AXIS2_PLACEMENT_3D", "x:real", "y:real", "z:real"),
    "POLYLINE": _NAME + ("points:list:ref:CARTESIAN_POINT",),
    "LINE": _NAME + ("pnt:ref:CARTESIAN_POINT", "dir:ref:VECTOR"),
    "CIRCLE": _NAME + ("position:ref:AXIS2_PLACEMENT_3D", "radius:real"),
    "HELIX": _NAME + ("position:ref:AXIS2_PLACEMENT_3D", "radius:real", "pitch:real"),
    "TRIMMED_CURVE": _NAME
    + (
        "basis_curve:ref:curve",
        "trim_1:list:any",
        "trim_2:list:any",
        "sense_agreement:bool",
        "master_representation:enum:CARTESIAN|PARAMETER|UNSPECIFIED",
    ),
    "COMPOSITE_CURVE": _NAME
    + ("segments:list:ref:COMPOSITE_CURVE_SEGMENT", "self_intersect:logical"),
    "COMPOSITE_CURVE_SEGMENT": (
        "transition:enum:DISCONTINUOUS|CONTINUOUS|CONT_SAME_GRADIENT"
        "|CONT_SAME_GRADIENT_SAME_CURVATURE",
        "same_sense:bool",
        "parent_curve:ref:curve",
    ),
    "B_SPLINE_CURVE_WITH_KNOTS": _NAME
    + (
        "degree:int",
        "control_points_list:list:ref:CARTESIAN_POINT",
        "curve_form:enum:POLYLINE_FORM|CIRCULAR_ARC|ELLIPTIC_ARC|PARABOLIC_ARC"
        "|HYPERBOLIC_ARC|UNSPECIFIED",
        "closed_curve:logical",
        "self_intersect:logical",
        "knot_multiplicities:list:int",
        "knots:list:real",
        "knot_spec:enum:UNIFORM_KNOTS|QUASI_UNIFORM_KNOTS|PIECEWISE_BEZIER_KNOTS|UNSPECIFIED",
    ),
}

#: the ISO 14649-12 turning operations (the 14649-121 part of the AP238 ed. 3 ARM)
TURNING_OPERATIONS = frozenset(
    {
        "FACING_ROUGH",
        "FACING_FINISH",
        "CONTOURING_ROUGH",
        "CONTOURING_FINISH",
        "GROOVING_ROUGH",
        "GROOVING_FINISH",
        "CUTTING_IN",
        "THREADING_ROUGH",
        "THREADING_FINISH",
        "KNURLING",
    }
)

#: abstract supertypes -> the instantiable entities accepted where they are referenced.
GROUPS: dict[str, frozenset[str]] = {
    "executable": frozenset(
        {
            "WORKPLAN",
            "NON_SEQUENTIAL",
            "PARALLEL",
            "SELECTIVE",
            "IF_STATEMENT",
            "WHILE_STATEMENT",
            "MACHINING_WORKINGSTEP",
            "RAPID_MOVEMENT",
            "DISPLAY_MESSAGE",
            "PROGRAM_STOP",
            "OPTIONAL_STOP",
            "LOAD_TOOL",
            "UNLOAD_TOOL",
            "EXCHANGE_PALLET",
        }
    ),
    "feature": frozenset(
        {"PLANAR_FACE", "CLOSED_POCKET", "OPEN_POCKET", "ROUND_HOLE", "SLOT", "STEP"}
    )
    | frozenset({"OUTER_DIAMETER", "REVOLVED_FLAT", "GROOVE", "GENERAL_REVOLUTION"}),
    "operation": frozenset(
        {
            "PLANE_ROUGH_MILLING",
            "PLANE_FINISH_MILLING",
            "SIDE_ROUGH_MILLING",
            "SIDE_FINISH_MILLING",
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            "FREEFORM_OPERATION",
            "DRILLING",
            "CENTER_DRILLING",
            "COUNTER_SINKING",
            "MULTISTEP_DRILLING",
            "REAMING",
            "BORING",
            "BACK_BORING",
            "TAPPING",
            "THREAD_DRILLING",
        }
    )
    | TURNING_OPERATIONS,
    "turning_strategy": frozenset(
        {
            "UNIDIRECTIONAL_TURNING",
            "BIDIRECTIONAL_TURNING",
            "CONTOUR_TURNING",
            "THREAD_STRATEGY",
            "GROOVING_STRATEGY",
            "MULTISTEP_GROOVING_STRATEGY",
            "EXPLICIT_TURNING_STRATEGY",
        }
    ),
    "speed_select": frozenset({"CONST_SPINDLE_SPEED", "CONST_CUTTING_SPEED"}),
    "corner": frozenset({"ROUNDED_CORNER", "CHAMFERED_CORNER"}),
    "bounding": frozenset({"BLOCK", "RIGHT_CIRCULAR_CYLINDER"}),
    "taper": frozenset({"DIAMETER_TAPER", "ANGLE_TAPER"}),
    "two5d_strategy": frozenset(
        {
            "UNIDIRECTIONAL_MILLING",
            "BIDIRECTIONAL_MILLING",
            "CONTOUR_PARALLEL",
            "CONTOUR_BIDIRECTIONAL",
            "CONTOUR_SPIRAL",
            "CENTER_MILLING",
        }
    ),
    "drilling_strategy": frozenset({"DRILLING_TYPE_STRATEGY"}),
    "approach": frozenset({"PLUNGE_TOOLAXIS", "PLUNGE_RAMP", "PLUNGE_ZIGZAG", "PLUNGE_HELIX"}),
    "tool": frozenset(
        {
            "MILLING_CUTTING_TOOL",
            "GENERAL_TURNING_TOOL",
            "GROOVING_TOOL",
            "TURNING_THREADING_TOOL",
            "KNURLING_TOOL",
        }
    ),
    "tool_body": frozenset(
        {
            "ENDMILL",
            "TAPERED_ENDMILL",
            "BALL_ENDMILL",
            "FACEMILL",
            "TWIST_DRILL",
            "CENTER_DRILL",
            "COUNTERSINK",
            "REAMER",
            "TAPERED_REAMER",
            "TAP",
        }
    ),
    "technology": frozenset({"MILLING_TECHNOLOGY", "TURNING_TECHNOLOGY"}),
    "machine_functions": frozenset({"MILLING_MACHINE_FUNCTIONS", "TURNING_MACHINE_FUNCTIONS"}),
    "surface": frozenset({"PLANE", "ELEMENTARY_SURFACE"}),
    "point": frozenset({"CARTESIAN_POINT"}),
    "numeric": frozenset({"NUMERIC_PARAMETER", "TOLERANCED_LENGTH_MEASURE"}),
    "closed_profile": frozenset(
        {"RECTANGULAR_CLOSED_PROFILE", "CIRCULAR_CLOSED_PROFILE", "GENERAL_CLOSED_PROFILE"}
    ),
    "open_profile": frozenset({"SQUARE_U_PROFILE", "GENERAL_PROFILE", "LINEAR_PROFILE"}),
    "travel_path": frozenset({"LINEAR_PATH"}),
    "hole_bottom": frozenset(
        {
            "THROUGH_BOTTOM_CONDITION",
            "FLAT_HOLE_BOTTOM",
            "FLAT_WITH_RADIUS_HOLE_BOTTOM",
            "CONICAL_HOLE_BOTTOM",
            "SPHERICAL_HOLE_BOTTOM",
        }
    ),
    "pocket_bottom": frozenset(
        {"PLANAR_POCKET_BOTTOM_CONDITION", "THROUGH_POCKET_BOTTOM_CONDITION"}
    ),
    "curve": frozenset(
        {
            "POLYLINE",
            "LINE",
            "CIRCLE",
            "HELIX",
            "TRIMMED_CURVE",
            "COMPOSITE_CURVE",
            "B_SPLINE_CURVE_WITH_KNOTS",
        }
    ),
    "toolpath": frozenset({"CUTTER_LOCATION_TRAJECTORY", "FEEDSTOP"}),
    "toolpath_list": frozenset({"TOOLPATH_LIST"}),
}


class Attr:
    """One parsed attribute spec."""

    __slots__ = ("name", "kind", "arg", "optional", "is_list")

    def __init__(self, spec: str) -> None:
        self.optional = spec.endswith("?")
        spec = spec.rstrip("?")
        self.name, _, typ = spec.partition(":")
        self.is_list = typ.startswith("list:")
        if self.is_list:
            typ = typ[5:]
        self.kind, _, self.arg = typ.partition(":")

    def describe(self) -> str:
        base = self.kind + (f" {self.arg}" if self.arg else "")
        return f"list of {base}" if self.is_list else base


ATTRS: dict[str, tuple[Attr, ...]] = {k: tuple(Attr(s) for s in v) for k, v in ENTITIES.items()}


def accepts(group: str, entity: str | None) -> bool:
    """Whether an instance of ``entity`` may stand where ``group`` is expected."""
    if not group or entity is None:
        return True
    return entity == group or entity in GROUPS.get(group, ())


def check_scalar(attr: Attr, value: object) -> str | None:
    """Type-check one non-list value (references only by kind); return a problem or None."""
    kind = attr.kind
    if isinstance(value, Typed):
        value = value.value
    if kind == "any":
        return None
    if kind == "label":
        return None if isinstance(value, str) and not isinstance(value, Enum) else "a string"
    if kind == "real":
        ok = isinstance(value, (int, float)) and not isinstance(value, (bool, Ref))
        return None if ok else "a number"
    if kind == "int":
        return None if type(value) is int else "an integer"
    if kind == "bool":
        return None if isinstance(value, Enum) and value in ("T", "F") else ".T. or .F."
    if kind == "logical":
        return None if isinstance(value, Enum) and value in ("T", "F", "U") else "a logical"
    if kind == "enum":
        options = attr.arg.split("|")
        if isinstance(value, Enum) and value in options:
            return None
        return "one of " + ", ".join(f".{o}." for o in options)
    if kind == "ref":
        return None if isinstance(value, Ref) else "a reference #n"
    return None
