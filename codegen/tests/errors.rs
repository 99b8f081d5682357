//! One test per error of the chain description language: the exact message and where it points
//! (line and column, through `parse_chain_str`), plus all errors of one file reported at once.
//!
//! Sources are built by [`chain`]: line 1 is `chain C {`, then one item per line, so the item at
//! index `k` is on line `k + 2` and columns count from the item's first character.

use std::path::Path;

use articulated_codegen::load::{load, parse_chain_str, Diagnostic, LoadError};
use articulated_codegen::lower::lower;
use articulated_codegen::parse::ChainDef;

/// A valid body `a` and the joint that hangs it from the world.
const B: &str = "body a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }";
const J: &str = "joint j: revolute(z) { parent: world, child: a }";

fn chain(items: &[&str]) -> String {
    format!("chain C {{\n{}\n}}\n", items.join("\n"))
}

fn diagnostics(src: &str) -> Vec<Diagnostic> {
    match parse_chain_str(src, Path::new("t.chain")) {
        Ok(m) => panic!("expected errors, got a model: {m:?}"),
        Err(e) => {
            assert_eq!(e.path, Path::new("t.chain"));
            e.diagnostics
        }
    }
}

/// Asserts that `items` give exactly one error, at `line:column`, with `message`.
#[track_caller]
fn check(items: &[&str], line: usize, column: usize, message: &str) {
    check_src(&chain(items), line, column, message);
}

#[track_caller]
fn check_src(src: &str, line: usize, column: usize, message: &str) {
    let d = diagnostics(src);
    assert_eq!(
        d,
        vec![Diagnostic {
            line,
            column,
            message: message.to_string()
        }],
        "source:\n{src}"
    );
}

const EULER: &str =
    "`xyz`, `xzy`, `yxz`, `yzx`, `zxy`, `zyx`, `xyx`, `xzx`, `yxy`, `yzy`, `zxz`, `zyz`";

// ---- settings ----

#[test]
fn unknown_setting() {
    check(
        &["gravty: none;", B, J],
        2,
        1,
        "unknown setting `gravty`: expected `gravity`, `scalar`, `outputs`, `accuracy`, \
         `lock`, `keep`, `quasi_static`, `frames`, `contacts`, `loops`, `lanes`, `grounds`, \
         `spheres`, `friction` or `restitution` (or `param`, `body`, `joint`, `frame` items)",
    );
}

#[test]
fn unknown_accuracy() {
    check(
        &["accuracy: exact;", B, J],
        2,
        11,
        "unknown accuracy `exact`: expected `fastest` or `robust`",
    );
}

#[test]
fn lock_of_an_unknown_joint() {
    check(
        &["lock: [elbow(0.3)];", B, J],
        2,
        8,
        "cannot lock `elbow`: no joint of that name",
    );
}

#[test]
fn lock_with_the_wrong_number_of_coordinates() {
    check(
        &["lock: [j(0.3, 0.1)];", B, J],
        2,
        8,
        "joint `j` is locked with 2 values but has 1 position coordinate",
    );
}

#[test]
fn lock_needs_joint_calls() {
    check(
        &["lock: [j];", B, J],
        2,
        8,
        "expected a joint and its position coordinates such as `elbow(0.3)`, found `j`",
    );
}

#[test]
fn keep_of_a_body_without_its_parent() {
    let b2 = "body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }";
    let j2 = "joint k: revolute(x) { parent: a, child: b }";
    check(
        &["keep: [b];", B, b2, J, j2],
        2,
        8,
        "body `b` is kept but its parent `a` is not: a sub-tree keeps every body between the \
         world and the bodies it names",
    );
    check(
        &["keep: [ghost];", B, J],
        2,
        8,
        "cannot keep `ghost`: no body of that name",
    );
}

#[test]
fn quasi_static_is_true_or_false() {
    check(
        &["quasi_static: yes;", B, J],
        2,
        15,
        "expected `true` or `false`, found `yes`",
    );
}

#[test]
fn duplicate_setting() {
    check(
        &["scalar: f64;", "scalar: f32;", B, J],
        3,
        1,
        "setting `scalar` is given twice",
    );
}

#[test]
fn unknown_scalar() {
    check(
        &["scalar: f16;", B, J],
        2,
        9,
        "unknown scalar `f16`: expected `f64`, `f32` or `generic`",
    );
}

#[test]
fn unknown_output() {
    check(
        &["outputs: [mass_matrix, mas_matrix];", B, J],
        2,
        24,
        "unknown output `mas_matrix`: did you mean `mass_matrix`? expected one of `mass_matrix`, `mass_matrix_update`, \
         `mass_matrix_lower`, `bias`, `gravity`, `inverse_dynamics`, `forward_dynamics`, \
         `nonlinear_effects`, \
         `mass_matrix_and_nonlinear_effects`, `joint_wrenches`, `joint_wrenches_bottom_up`, \
         `center_of_mass`, `center_of_mass_velocity`, `center_of_mass_jacobian`, \
         `centroidal_momentum`, `centroidal_momentum_matrix`, `centroidal_momentum_rate`, \
         `centroidal_momentum_drift`, `kinetic_energy`, \
         `potential_energy`, `coriolis_matrix`, `inverse_dynamics_derivatives`, \
         `forward_dynamics_derivatives`, `mass_matrix_inverse`, `frame_placements`, \
         `frame_velocities`, `frame_accelerations`, `frame_velocity_derivatives`, \
         `frame_acceleration_derivatives`, `frame_jacobians_local`, \
         `frame_jacobians_world`, `frame_jacobians_local_world_aligned`, \
         `frame_jacobian_time_variations_local`, `frame_jacobian_time_variations_world` or \
         `frame_jacobian_time_variations_local_world_aligned`, or a group: `dynamics`, \
         `kept`, `wrenches`, `whole_body`, `derivatives` or `frames`",
    );
}

#[test]
fn outputs_not_a_list() {
    check(
        &["outputs: mass_matrix;", B, J],
        2,
        10,
        "expected a list of outputs such as `[mass_matrix, bias]`, found `mass_matrix`",
    );
}

#[test]
fn gravity_wrong_shape() {
    check(
        &["gravity: [0.0, -9.81];", B, J],
        2,
        10,
        "expected `none` or a list of 3 numbers `[x, y, z]` for `gravity`, found `[0.0, -9.81]`",
    );
}

// ---- parameters and numbers ----

#[test]
fn duplicate_parameter() {
    check(
        &["param m = 1.0;", "param m = 2.0;", B, J],
        3,
        7,
        "parameter `m` is declared twice",
    );
}

#[test]
fn parameter_named_pi() {
    check(
        &["param pi = 3.0;", B, J],
        2,
        7,
        "`pi` is the constant π and cannot name a parameter: expected another name",
    );
}

#[test]
fn parameter_in_a_default() {
    check(
        &["param a = 1.0;", "param b = a;", B, J],
        3,
        11,
        "parameter `a` cannot be used in the default of parameter `b`: expected a constant",
    );
}

#[test]
fn unknown_parameter() {
    check(
        &[
            "param m = 1.0;",
            "body a { mass: n, inertia: diag(1.0, 1.0, 1.0) }",
            J,
        ],
        3,
        16,
        "unknown parameter `n`: expected a number, `pi` or a parameter: `m`",
    );
}

#[test]
fn unknown_parameter_none_declared() {
    check(
        &[
            "body a { mass: 1.0, com: [0.0, 0.0, l], inertia: diag(1.0, 1.0, 1.0) }",
            J,
        ],
        2,
        37,
        "unknown parameter `l`: expected a number or `pi` (no parameters are declared)",
    );
}

#[test]
fn parameter_inside_an_expression() {
    check(
        &[
            "param m = 1.0;",
            "body a { mass: 2.0 * m, inertia: diag(1.0, 1.0, 1.0) }",
            J,
        ],
        3,
        22,
        "parameter `m` cannot be used inside an expression: expected a parameter standing \
         alone (such as `mass: m`) or a constant expression",
    );
}

#[test]
fn parameter_in_an_axis() {
    check(
        &[
            "param s = 1.0;",
            B,
            "joint j: revolute([0.0, 0.0, s]) { parent: world, child: a }",
        ],
        4,
        30,
        "parameter `s` cannot be used in a joint axis: expected a constant",
    );
}

#[test]
fn non_finite_literal() {
    check(
        &["body a { mass: 1e999, inertia: diag(1.0, 1.0, 1.0) }", J],
        2,
        16,
        "`1e999` is not a finite number: it overflows f64; expected a finite value",
    );
}

#[test]
fn non_finite_expression() {
    check(
        &[
            B,
            "joint j: revolute(z) { parent: world, child: a, xyz: [1.0 / 0.0, 0.0, 0.0] }",
        ],
        3,
        55,
        "`1.0 / 0.0` is not a finite number: it evaluates to inf; expected a finite value",
    );
}

#[test]
fn number_with_suffix() {
    check(
        &["body a { mass: 1.0f32, inertia: diag(1.0, 1.0, 1.0) }", J],
        2,
        16,
        "unexpected suffix `f32` on `1.0f32`: expected a plain number (the scalar is chosen by \
         the `scalar` setting)",
    );
}

#[test]
fn list_where_a_number_stands() {
    check(
        &["body a { mass: [1.0], inertia: diag(1.0, 1.0, 1.0) }", J],
        2,
        16,
        "expected a number, found `[1.0]`",
    );
}

// ---- bodies ----

#[test]
fn duplicate_body() {
    check(&[B, B, J], 3, 6, "body `a` is declared twice");
}

#[test]
fn body_named_world() {
    check(
        &[
            B,
            "body world { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
            J,
        ],
        3,
        6,
        "`world` is the fixed frame every chain hangs from, not a body: expected another body \
         name",
    );
}

#[test]
fn unknown_body_field() {
    check(
        &[
            "body a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0), colour: 1.0 }",
            J,
        ],
        2,
        51,
        "unknown field `colour` in body `a`: expected `mass`, `com` or `inertia`",
    );
}

#[test]
fn duplicate_body_field() {
    check(
        &[
            "body a { mass: 1.0, mass: 2.0, inertia: diag(1.0, 1.0, 1.0) }",
            J,
        ],
        2,
        21,
        "field `mass` is given twice in body `a`",
    );
}

#[test]
fn missing_mass() {
    check(
        &["body a { inertia: diag(1.0, 1.0, 1.0) }", J],
        2,
        6,
        "body `a` is missing the required field `mass`",
    );
}

#[test]
fn missing_inertia() {
    check(
        &["body a { mass: 1.0 }", J],
        2,
        6,
        "body `a` is missing the required field `inertia`",
    );
}

#[test]
fn com_wrong_shape() {
    check(
        &[
            "body a { mass: 1.0, com: [0.0, 0.0], inertia: diag(1.0, 1.0, 1.0) }",
            J,
        ],
        2,
        26,
        "expected a list of 3 numbers `[x, y, z]` for `com`, found `[0.0, 0.0]`",
    );
}

#[test]
fn inertia_wrong_form() {
    check(
        &["body a { mass: 1.0, inertia: diag(1.0, 1.0) }", J],
        2,
        30,
        "expected `diag(ixx, iyy, izz)` or `[[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, \
         izz]]` for `inertia`, found `diag(1.0, 1.0)`",
    );
}

#[test]
fn inertia_row_wrong() {
    check(
        &[
            "body a { mass: 1.0, inertia: [[1.0, 0.0, 0.0], [0.0, 1.0], [0.0, 0.0, 1.0]] }",
            J,
        ],
        2,
        48,
        "expected row 2 of `inertia` to be a list of 3 numbers, found `[0.0, 1.0]`",
    );
}

#[test]
fn zero_mass_on_a_moving_body() {
    check(
        &["body a { mass: 0.0, inertia: diag(1.0, 1.0, 1.0) }", J],
        2,
        16,
        "mass of body `a` is 0: expected a positive number, since `a` moves (only bodies fixed \
         to the world may be massless)",
    );
}

#[test]
fn zero_mass_parameter_on_a_moving_body() {
    check(
        &[
            "param m = 0.0;",
            "body a { mass: m, inertia: diag(1.0, 1.0, 1.0) }",
            J,
        ],
        3,
        16,
        "mass of body `a` is `m` = 0 (its default): expected a positive number, since `a` \
         moves (only bodies fixed to the world may be massless)",
    );
}

#[test]
fn negative_mass_even_when_fixed() {
    check(
        &[
            "body a { mass: -1.0, inertia: diag(1.0, 1.0, 1.0) }",
            "joint j: fixed { parent: world, child: a }",
        ],
        2,
        16,
        "mass of body `a` is -1: expected zero or a positive number",
    );
}

#[test]
fn inertia_not_symmetric() {
    check(
        &[
            "body a { mass: 1.0, inertia: [[1.0, 0.1, 0.0], [0.2, 1.0, 0.0], [0.0, 0.0, 1.0]] }",
            J,
        ],
        2,
        49,
        "inertia of body `a` is not symmetric: `iyx` is `0.2` but `ixy` is `0.1`; expected \
         equal elements across the diagonal",
    );
}

#[test]
fn inertia_not_positive_definite_diag() {
    check(
        &["body a { mass: 1.0, inertia: diag(1.0, 0.0, 1.0) }", J],
        2,
        40,
        "inertia of body `a` is not positive definite: its principal moments are 0, 1, 1; \
         expected all positive",
    );
}

#[test]
fn inertia_not_positive_definite_matrix() {
    // Eigenvalues −1, 1, 3.
    check(
        &[
            "body a { mass: 1.0, inertia: [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]] }",
            J,
        ],
        2,
        30,
        "inertia of body `a` is not positive definite: its principal moments are -1, 1, 3; \
         expected all positive",
    );
}

#[test]
fn inertia_triangle_inequality_diag() {
    check(
        &["body a { mass: 1.0, inertia: diag(1.0, 1.0, 3.0) }", J],
        2,
        30,
        "inertia of body `a` breaks the triangle inequality: principal moments 1 + 1 < 3; \
         expected each moment to be at most the sum of the other two",
    );
}

#[test]
fn inertia_triangle_inequality_matrix() {
    // Eigenvalues 1, 3, 5: positive definite, but 1 + 3 < 5.
    check(
        &[
            "body a { mass: 1.0, inertia: [[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]] }",
            J,
        ],
        2,
        30,
        "inertia of body `a` breaks the triangle inequality: principal moments 1 + 3 < 5; \
         expected each moment to be at most the sum of the other two",
    );
}

// ---- joints ----

#[test]
fn duplicate_joint() {
    check(
        &[
            B,
            "body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
            J,
            "joint j: revolute(z) { parent: a, child: b }",
        ],
        5,
        7,
        "joint `j` is declared twice",
    );
}

#[test]
fn duplicate_joint_copied_whole_is_reported_once() {
    check(&[B, J, J], 4, 7, "joint `j` is declared twice");
}

#[test]
fn unknown_joint_kind() {
    check(
        &[B, "joint j: revolut(z) { parent: world, child: a }"],
        3,
        10,
        "unknown joint kind `revolut`: expected `revolute`, `prismatic`, `spherical`, `free` or \
         `fixed`",
    );
}

#[test]
fn revolute_without_axis() {
    check(
        &[B, "joint j: revolute { parent: world, child: a }"],
        3,
        10,
        "`revolute` takes one axis: expected `revolute(x)`, `revolute(y)`, `revolute(z)` or \
         `revolute([ax, ay, az])`, found `revolute`",
    );
}

#[test]
fn unknown_axis() {
    check(
        &[B, "joint j: prismatic(w) { parent: world, child: a }"],
        3,
        20,
        "unknown axis `w`: expected `x`, `y`, `z` (or `-x`, `-y`, `-z`) or a vector `[ax, ay, az]`",
    );
}

#[test]
fn zero_axis() {
    check(
        &[
            B,
            "joint j: revolute([0.0, 0.0, 0.0]) { parent: world, child: a }",
        ],
        3,
        19,
        "the axis of joint `j` is zero: expected a nonzero vector, found `[0.0, 0.0, 0.0]`",
    );
}

#[test]
fn spherical_without_rotation() {
    check(
        &[B, "joint j: spherical { parent: world, child: a }"],
        3,
        10,
        &format!(
            "`spherical` takes one rotation: expected `spherical(quaternion)` or \
             `spherical(SEQ)` with an Euler sequence SEQ ({EULER}), found `spherical`"
        ),
    );
}

#[test]
fn invalid_euler_sequence() {
    check(
        &[B, "joint j: spherical(xxy) { parent: world, child: a }"],
        3,
        20,
        &format!(
            "invalid Euler sequence `xxy`: expected `quaternion` or one of the 12 valid \
             sequences {EULER}"
        ),
    );
}

#[test]
fn free_with_two_rotations() {
    check(
        &[
            B,
            "joint j: free(zyx, quaternion) { parent: world, child: a }",
        ],
        3,
        10,
        &format!(
            "`free` takes at most one rotation: expected `free`, `free(quaternion)` or \
             `free(SEQ)` with an Euler sequence SEQ ({EULER}), found `free(zyx, quaternion)`"
        ),
    );
}

#[test]
fn fixed_with_arguments() {
    check(
        &[B, "joint j: fixed(z) { parent: world, child: a }"],
        3,
        10,
        "`fixed` takes no arguments: expected `fixed`, found `fixed(z)`",
    );
}

#[test]
fn unknown_joint_field() {
    check(
        &[
            B,
            "joint j: revolute(z) { parent: world, child: a, axis: z }",
        ],
        3,
        49,
        "unknown field `axis` in joint `j`: expected `parent`, `child`, `xyz`, `rpy`, \
         `armature`, `damping`, `friction`, `lower`, `upper`, `velocity`, `effort`, `mimic`, \
         `multiplier` or `offset`",
    );
}

#[test]
fn negative_armature() {
    check(
        &[
            B,
            "joint j: revolute(z) { parent: world, child: a, armature: -0.1 }",
        ],
        3,
        49,
        "joint `j`: armature must be finite and >= 0, found -0.1",
    );
}

#[test]
fn limits_upside_down() {
    check(
        &[
            B,
            "joint j: revolute(z) { parent: world, child: a, lower: 1.0, upper: -1.0 }",
        ],
        3,
        49,
        "joint `j`: limits must satisfy lower <= upper, found [1, -1]",
    );
}

#[test]
fn limits_on_a_spherical_joint() {
    check(
        &[
            B,
            "joint j: spherical(xyz) { parent: world, child: a, upper: 1.0 }",
        ],
        3,
        52,
        "joint `j`: position limits apply to revolute and prismatic joints only",
    );
}

#[test]
fn zero_effort_limit() {
    check(
        &[
            B,
            "joint j: revolute(z) { parent: world, child: a, damping: 0.1, effort: 0.0 }",
        ],
        3,
        63,
        "joint `j`: the effort limit must be > 0, found 0",
    );
}

#[test]
fn parameter_in_a_drive() {
    check_src(
        "chain C {\nparam k = 0.1;\nbody a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }\n\
         joint j: revolute(z) { parent: world, child: a, damping: k }\n}\n",
        4,
        58,
        "parameter `k` cannot be used in a joint's `damping`: expected a constant",
    );
}

#[test]
fn duplicate_joint_field() {
    check(
        &[
            B,
            "joint j: revolute(z) { parent: world, parent: world, child: a }",
        ],
        3,
        39,
        "field `parent` is given twice in joint `j`",
    );
}

#[test]
fn missing_parent() {
    check(
        &[B, "joint j: revolute(z) { child: a }"],
        3,
        7,
        "joint `j` is missing the required field `parent`",
    );
}

#[test]
fn missing_child() {
    check(
        &[B, "joint j: revolute(z) { parent: world }"],
        3,
        7,
        "joint `j` is missing the required field `child`",
    );
}

#[test]
fn unknown_parent() {
    check(
        &[B, "joint j: revolute(z) { parent: wrld, child: a }"],
        3,
        32,
        "unknown body `wrld` as parent of joint `j`: expected `world` or a body (`a`)",
    );
}

#[test]
fn unknown_child() {
    check(
        &[B, "joint j: revolute(z) { parent: world, child: b }"],
        3,
        46,
        "unknown body `b` as child of joint `j`: expected a body (`a`)",
    );
}

#[test]
fn parent_not_a_name() {
    check(
        &[B, "joint j: revolute(z) { parent: [0], child: a }"],
        3,
        32,
        "expected `world` or a body name as parent of joint `j`, found `[0]`",
    );
}

#[test]
fn world_as_child() {
    check(
        &[B, "joint j: revolute(z) { parent: world, child: world }"],
        3,
        46,
        "`world` cannot be the child of joint `j`: the world does not move; expected a body",
    );
}

#[test]
fn body_with_two_parents() {
    check(
        &[
            B,
            "body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
            J,
            "joint k: revolute(z) { parent: a, child: b }",
            "joint l: revolute(z) { parent: world, child: b }",
        ],
        6,
        46,
        "body `b` has two parents: it is already the child of joint `k`; expected each body to \
         be the child of exactly one joint",
    );
}

#[test]
fn body_without_parent() {
    check(
        &[B, "body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }", J],
        3,
        6,
        "body `b` has no parent: expected a joint with `child: b`",
    );
}

#[test]
fn cycle() {
    check(
        &[
            B,
            "body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
            "body c { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
            J,
            "joint k: revolute(z) { parent: c, child: b }",
            "joint l: revolute(z) { parent: b, child: c }",
        ],
        6,
        32,
        "joints form a cycle `c` → `b` → `c`: none of these bodies is reachable from `world`; \
         expected a tree hanging from `world`",
    );
}

// ---- the chain as a whole ----

#[test]
fn unsupported_attribute() {
    check_src(
        &format!("#[inline]\n{}", chain(&[B, J])),
        1,
        1,
        "unsupported attribute `#[inline]` before `chain`: expected only doc comments (`/// …`)",
    );
}

#[test]
fn no_bodies() {
    check(
        &["scalar: f64;"],
        1,
        7,
        "chain `C` has no bodies: expected at least one `body` and a `joint` attaching it to \
         `world`",
    );
}

// ---- syntax and tokens: the first error stops parsing ----

#[test]
fn syntax_error_at_the_token() {
    check(
        &["body a { mass 1.0, inertia: diag(1.0, 1.0, 1.0) }", J],
        2,
        15,
        "expected `:`",
    );
}

#[test]
fn unknown_item() {
    check(
        &["bodies a { mass: 1.0 }", J],
        2,
        1,
        "expected `body name { … }`, `joint name: kind { … }`, `frame name { … }`, \
         `param name = value;` or a setting `key: value;`",
    );
}

#[test]
fn not_a_chain() {
    check_src("struct C { }", 1, 1, "expected `chain Name { … }`");
}

#[test]
fn end_of_input() {
    check_src(
        "pub chain\n",
        1,
        10,
        "unexpected end of input, expected identifier",
    );
}

#[test]
fn unclosed_delimiter() {
    check_src(
        "chain C {\n    body a { mass: 1.0,\n",
        2,
        12,
        "unclosed delimiter `{`: expected a matching `}` before the end of the file",
    );
}

#[test]
fn unmatched_closing_delimiter() {
    check_src(
        "chain C {\n    body a { mass: 1.0 ]\n}\n",
        2,
        24,
        "unexpected closing delimiter `]`: it does not match the innermost open delimiter",
    );
}

#[test]
fn unreadable_file() {
    let path = Path::new("/nonexistent/dir/robot.chain");
    let err = load(path, false).unwrap_err();
    assert!(matches!(err, LoadError::Read { .. }), "{err:?}");
    let shown = err.to_string();
    assert!(
        shown.starts_with("/nonexistent/dir/robot.chain: error: cannot read: "),
        "{shown}"
    );
}

#[test]
fn no_panic_on_prefixes_and_deletions_of_a_valid_file() {
    let src = include_str!("fixtures/two_link.chain");
    let mut variants = Vec::new();
    for (at, ch) in src.char_indices() {
        variants.push(src[..at].to_string());
        variants.push(format!("{}{}", &src[..at], &src[at + ch.len_utf8()..]));
    }
    for v in &variants {
        if let Err(e) = parse_chain_str(v, Path::new("t.chain")) {
            assert!(!e.diagnostics.is_empty(), "{v}");
            for d in &e.diagnostics {
                assert!(d.line >= 1 && d.column >= 1, "{v}\n{d:?}");
            }
        }
    }
}

// ---- all errors at once ----

#[test]
fn every_error_of_a_file_is_reported() {
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/many_errors.chain"
    ));
    let Err(LoadError::Chain(err)) = load(path, false) else {
        panic!("expected errors in {}", path.display());
    };
    let got: Vec<(usize, usize, &str)> = err
        .diagnostics
        .iter()
        .map(|d| (d.line, d.column, d.message.as_str()))
        .collect();
    assert_eq!(
        got,
        vec![
            (
                3,
                13,
                "unknown scalar `f16`: expected `f64`, `f32` or `generic`"
            ),
            (
                6,
                15,
                "mass of body `legs` is -30: expected a positive number"
            ),
            (
                7,
                18,
                "inertia of body `legs` breaks the triangle inequality: principal moments \
                 0.25 + 0.5 < 2.6; expected each moment to be at most the sum of the other two"
            ),
            (
                9,
                10,
                "body `trunk` is missing the required field `inertia`"
            ),
            (
                9,
                24,
                "unknown parameter `trunk_mas`: expected a number, `pi` or a parameter: \
                 `trunk_mass`"
            ),
            (
                11,
                28,
                "invalid Euler sequence `xyx2`: expected `quaternion` or one of the 12 valid \
                 sequences `xyz`, `xzy`, `yxz`, `yzx`, `zxy`, `zyx`, `xyx`, `xzx`, `yxy`, \
                 `yzy`, `zxz`, `zyz`"
            ),
            (
                12,
                41,
                "unknown body `leg` as parent of joint `hip`: expected `world` or a body \
                 (`legs`, `trunk`)"
            ),
        ]
    );
    // Displayed one per line as `path:line:column: error: message`.
    let shown = err.to_string();
    let lines: Vec<&str> = shown.lines().collect();
    assert_eq!(lines.len(), 7);
    assert_eq!(
        lines[0],
        format!(
            "{}:3:13: error: unknown scalar `f16`: expected `f64`, `f32` or `generic`",
            path.display()
        )
    );
}

#[test]
fn lower_combines_all_errors_for_the_macro() {
    let def: ChainDef = syn::parse_str(&chain(&[
        "scalar: f16;",
        "body a { mass: 0.0, inertia: diag(1.0, 1.0, 1.0) }",
        "joint j: revolute(w) { parent: world, child: a }",
    ]))
    .expect("syntax is fine");
    let err = lower(&def).unwrap_err();
    // In source order, whatever order the checks run in.
    let messages: Vec<String> = err.into_iter().map(|e| e.to_string()).collect();
    assert_eq!(
        messages,
        vec![
            "unknown scalar `f16`: expected `f64`, `f32` or `generic`",
            "mass of body `a` is 0: expected a positive number, since `a` moves (only bodies \
             fixed to the world may be massless)",
            "unknown axis `w`: expected `x`, `y`, `z` (or `-x`, `-y`, `-z`) or a vector `[ax, ay, az]`",
        ]
    );
}

/// Two bodies on revolute joints and a third joint `k` mimicking `extra`, for the mimic errors.
const B2: &str = "body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }";

#[test]
fn mimic_of_an_unknown_joint() {
    check(
        &[
            B,
            J,
            B2,
            "joint k: revolute(z) { parent: a, child: b, mimic: ghost }",
        ],
        5,
        52,
        "joint `k` mimics `ghost`, which is not a joint: expected one of `j`, `k`",
    );
}

#[test]
fn mimic_of_itself() {
    check(
        &[
            B,
            J,
            B2,
            "joint k: revolute(z) { parent: a, child: b, mimic: k }",
        ],
        5,
        52,
        "joint `k` mimics `k`, itself: a joint cannot mimic itself",
    );
}

#[test]
fn mimic_of_a_spherical_joint() {
    check(
        &[
            B,
            "joint j: spherical(xyz) { parent: world, child: a }",
            B2,
            "joint k: revolute(z) { parent: a, child: b, mimic: j }",
        ],
        5,
        52,
        "joint `k` mimics `j`, which is not revolute or prismatic: only revolute and prismatic \
         joints mimic and are mimicked",
    );
}

#[test]
fn mimic_of_a_mimic_joint() {
    check(
        &[
            B,
            J,
            B2,
            "joint k: revolute(z) { parent: a, child: b, mimic: j }",
            "body c { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
            "joint l: revolute(z) { parent: b, child: c, mimic: k }",
        ],
        7,
        52,
        "joint `l` mimics `k`, which is a mimic joint itself: mimic the joint that one follows, \
         with the multipliers and offsets composed",
    );
}

#[test]
fn multiplier_without_mimic() {
    check(
        &[
            B,
            J,
            B2,
            "joint k: revolute(z) { parent: a, child: b, multiplier: 2.0 }",
        ],
        5,
        45,
        "joint `k`: `multiplier` needs `mimic: <joint>`",
    );
}

#[test]
fn limits_on_a_mimic_joint() {
    check(
        &[
            B,
            J,
            B2,
            "joint k: revolute(z) { parent: a, child: b, mimic: j, upper: 1.0 }",
        ],
        5,
        52,
        "joint `k` mimics `j`, but a mimic joint has no coordinate, so no damping, friction or \
         limits of its own (its armature is allowed: it is inertia)",
    );
}

#[test]
fn lock_of_a_mimic_joint() {
    check(
        &[
            "lock: [k(0.3)];",
            B,
            J,
            B2,
            "joint k: revolute(z) { parent: a, child: b, mimic: j }",
        ],
        2,
        8,
        "joint `k` mimics another joint, which moves: a mimic joint is locked with the joint it \
         follows (lock or drop that one) and moves with it",
    );
}

// ---- the check stage: outputs and options that do not go with the model ----

/// A hub with two arms, the second following the first (a branching tree with a mimic joint).
const HUB: [&str; 6] = [
    "body hub { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
    "body left { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
    "body right { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
    "joint base: revolute(z) { parent: world, child: hub }",
    "joint l: revolute(y) { parent: hub, child: left }",
    "joint r: revolute(y) { parent: hub, child: right, mimic: l }",
];

#[test]
fn bottom_up_wrenches_on_a_branching_tree() {
    let mut items = vec!["outputs: [mass_matrix, joint_wrenches_bottom_up];"];
    items.extend(HUB);
    check(
        &items,
        2,
        24,
        "`joint_wrenches_bottom_up` needs a serial chain, and `C` branches: where a body has two \
         children, how the wrench splits between them is not determined; use `joint_wrenches` \
         (from the free ends down)",
    );
}

#[test]
fn robust_forward_dynamics_with_a_mimic_joint() {
    let mut items = vec!["accuracy: robust;"];
    items.extend(HUB);
    check(
        &items,
        2,
        11,
        "`accuracy: robust` keeps forward dynamics to ABA, which cannot run with mimic joints \
         (`r` follows another joint, so one coordinate moves two branches); use `accuracy: \
         fastest` (CRBA + LᵀDL of the coupled M)",
    );
}

/// What a scene leaves is what the options are judged on: bottom-up wrenches on the hub's
/// trunk alone, with both arms locked, are fine.
#[test]
fn bottom_up_wrenches_on_a_scene_that_is_serial() {
    let mut items = vec!["outputs: [joint_wrenches_bottom_up];", "lock: [l(0.0)];"];
    items.extend(HUB);
    parse_chain_str(&chain(&items), Path::new("t.chain")).unwrap_or_else(|e| panic!("{e}"));
}

/// Every rule of the check stage a description breaks is reported at once, each at its token,
/// with the errors of names and values: an inertia that breaks the triangle inequality, a cycle
/// (so no model can be built, and the options are judged on the joints as declared), a mimic
/// joint under `accuracy: robust`, bottom-up wrenches on a branching tree, an unknown body.
#[test]
fn every_rule_of_the_check_stage_is_reported_at_once() {
    let src = "chain Broken {
    outputs: [forward_dynamics, joint_wrenches_bottom_up];
    accuracy: robust;
    body hub { mass: 1.0, inertia: diag(1.0, 1.0, 3.0) }
    body left { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
    body right { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
    body p { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
    body q { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
    body s { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
    joint base: revolute(z) { parent: world, child: hub }
    joint l: revolute(y) { parent: hub, child: left }
    joint r: revolute(y) { parent: hub, child: right, mimic: l }
    joint pq: revolute(x) { parent: p, child: q }
    joint qp: revolute(x) { parent: q, child: p }
    joint ghost: revolute(x) { parent: nowhere, child: s }
}
";
    let got: Vec<(usize, usize, String)> = diagnostics(src)
        .into_iter()
        .map(|d| (d.line, d.column, d.message))
        .collect();
    let want: Vec<(usize, usize, &str)> = vec![
        (
            2,
            33,
            "`joint_wrenches_bottom_up` needs a serial chain, and `Broken` branches: where a body \
             has two children, how the wrench splits between them is not determined; use \
             `joint_wrenches` (from the free ends down)",
        ),
        (
            3,
            15,
            "`accuracy: robust` keeps forward dynamics to ABA, which cannot run with mimic joints \
             (`r` follows another joint, so one coordinate moves two branches); use `accuracy: \
             fastest` (CRBA + LᵀDL of the coupled M)",
        ),
        (
            4,
            36,
            "inertia of body `hub` breaks the triangle inequality: principal moments 1 + 1 < 3; \
             expected each moment to be at most the sum of the other two",
        ),
        (
            13,
            37,
            "joints form a cycle `q` → `p` → `q`: none of these bodies is reachable from \
             `world`; expected a tree hanging from `world`",
        ),
        (
            15,
            40,
            "unknown body `nowhere` as parent of joint `ghost`: expected `world` or a body \
             (`hub`, `left`, `right`, `p`, `q`, `s`)",
        ),
    ];
    let got: Vec<(usize, usize, &str)> = got.iter().map(|(l, c, m)| (*l, *c, m.as_str())).collect();
    assert_eq!(got, want);
}

/// A `Builder` given options that do not go with a description's model (it has no token to
/// point at) reports every problem at once, one line each, naming the description.
#[test]
fn a_builder_reports_every_problem_of_its_options_at_once() {
    use articulated_codegen::options::{Accuracy, Output};
    use articulated_codegen::Builder;
    let d = parse_chain_str(&chain(&HUB), Path::new("hub.chain")).unwrap_or_else(|e| panic!("{e}"));
    let e = Builder::new()
        .description(d)
        .outputs([Output::ForwardDynamics, Output::JointWrenchesBottomUp])
        .accuracy(Accuracy::Robust)
        .to_source()
        .unwrap_err()
        .to_string();
    let lines: Vec<&str> = e.lines().collect();
    assert_eq!(lines.len(), 2, "{e}");
    assert!(
        lines[0].starts_with("the model `C`: `joint_wrenches_bottom_up` needs a serial chain"),
        "{e}"
    );
    assert!(
        lines[1].starts_with("the model `C`: `accuracy: robust` keeps forward dynamics to ABA"),
        "{e}"
    );
}

// ---- frames ----

const OUT: &str = "outputs: [frame_placements];";

#[test]
fn frame_with_an_unknown_parent() {
    check(
        &[
            B,
            J,
            OUT,
            "frames: [tip];",
            "frame tip { parent: b, xyz: [0.0, 0.0, 1.0] }",
        ],
        6,
        21,
        "unknown body `b` as parent of frame `tip`: expected `world` or a body (`a`)",
    );
}

#[test]
fn frame_without_a_parent() {
    check(
        &[
            B,
            J,
            OUT,
            "frames: [tip];",
            "frame tip { xyz: [0.0, 0.0, 1.0] }",
        ],
        6,
        7,
        "frame `tip` is missing the required field `parent`",
    );
}

#[test]
fn frame_named_as_a_body_or_twice() {
    check(
        &[B, J, OUT, "frames: [a];", "frame a { parent: a }"],
        6,
        7,
        "frame `a` has the name of a body, which is a frame already: every body is a frame \
         under its own name; name this one otherwise",
    );
    check(
        &[
            B,
            J,
            OUT,
            "frames: [t];",
            "frame t { parent: a }",
            "frame t { parent: world }",
        ],
        7,
        7,
        "frame `t` is declared twice",
    );
}

#[test]
fn unknown_field_in_a_frame() {
    check(
        &[
            B,
            J,
            OUT,
            "frames: [t];",
            "frame t { parent: a, mass: 1.0 }",
        ],
        6,
        22,
        "unknown field `mass` in frame `t`: expected `parent`, `xyz` or `rpy`",
    );
}

#[test]
fn frames_that_do_not_exist_or_are_named_twice() {
    check(
        &[B, J, OUT, "frames: [a, tool];"],
        5,
        13,
        "unknown frame `tool`: expected a body or a frame of `C` (`a`)",
    );
    check(
        &[B, J, OUT, "frames: [a, a];"],
        5,
        13,
        "frame `a` is named twice in `frames`",
    );
}

#[test]
fn frame_outputs_need_frames_and_frames_need_a_frame_output() {
    check(
        &[B, J, "outputs: [mass_matrix, frame_velocities];"],
        4,
        24,
        "`frame_velocities` computes the frames named in `frames: [...]`, and none is named: \
         name them, e.g. `frames: [tool]` (a body's name, a `frame` item's, a URDF link's)",
    );
    check(
        &[B, J, "frames: [a];"],
        4,
        10,
        "`frames` names frames, but no frame output is generated: add one to `outputs` \
         (`frame_placements`, `frame_jacobians_local_world_aligned`, …, or the group `frames`)",
    );
}

// ---- constraints: `contacts` and `loops` ----

/// A free body `a` (6 velocities), a body `b` on a ball joint under it (3 more), frames `tip`
/// and `toe` on `b`, `anchor` on the world.
const FREE: [&str; 7] = [
    "body a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
    "joint j: free { parent: world, child: a }",
    "body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }",
    "joint k: spherical(xyz) { parent: a, child: b }",
    "frame tip { parent: b, xyz: [0.0, 0.0, 1.0] }",
    "frame toe { parent: b, xyz: [0.5, 0.0, 1.0] }",
    "frame anchor { parent: world }",
];

/// Asserts that the setting `setting` (line 2) after [`FREE`] gives one error at `column`.
#[track_caller]
fn check_constraint(setting: &str, column: usize, message: &str) {
    let mut items = vec![setting];
    items.extend(FREE);
    check(&items, 2, column, message);
}

const KINDS: &str = "expected `six_d` (the whole frame held: 6 rows, a wrench in its axes) or \
                     `point` (its origin held: 3 rows, a force in world axes)";

#[test]
fn contacts_and_loops_that_hold() {
    // No error: a contact and a loop, their frames and outputs added where absent.
    let src = chain(
        &[
            &[
                "outputs: [mass_matrix];",
                "frames: [toe];",
                "contacts: [tip: six_d];",
                "loops: [rod: point(toe, anchor)];",
            ][..],
            &FREE[..],
        ]
        .concat(),
    );
    let d = parse_chain_str(&src, Path::new("t.chain")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(d.options.constraint_rows(), 9);
    let resolved = d.options.resolved();
    assert_eq!(resolved.frames, ["toe", "tip", "anchor"]);
    assert_eq!(resolved.outputs.len(), 6);
    // Without constraints, nothing changes.
    let plain = parse_chain_str(&chain(&FREE), Path::new("t.chain")).unwrap();
    assert_eq!(plain.options.resolved(), plain.options);
}

#[test]
fn unknown_contact_kind() {
    check_constraint(
        "contacts: [tip: plane];",
        17,
        &format!("unknown contact kind `plane`: {KINDS}"),
    );
    check_constraint(
        "contacts: [tip: sixd];",
        17,
        &format!("unknown contact kind `sixd`: did you mean `six_d`? {KINDS}"),
    );
}

#[test]
fn contact_on_an_unknown_frame() {
    check_constraint(
        "contacts: [tpi: point];",
        12,
        "unknown frame `tpi`: did you mean `tip`? expected a body or a frame of `C` (`a`, \
         `anchor`, `b`, `tip`, `toe`)",
    );
    check_constraint(
        "contacts: [hand: point];",
        12,
        "unknown frame `hand`: expected a body or a frame of `C` (`a`, `anchor`, `b`, `tip`, \
         `toe`)",
    );
}

#[test]
fn contact_declared_twice() {
    check_constraint(
        "contacts: [tip: point, tip: six_d];",
        24,
        "contact `tip` is declared twice in `contacts`: a frame holds one contact (a `six_d` \
         contact holds its origin too)",
    );
}

#[test]
fn malformed_contacts() {
    check_constraint(
        "contacts: tip;",
        11,
        "expected a list of contacts such as `[left_sole: six_d, toe: point]`, found `tip`",
    );
    check_constraint(
        "contacts: [tip];",
        12,
        "expected a contact `frame: kind` such as `left_sole: six_d`, found `tip`",
    );
    check_constraint(
        "contacts: [tip: point(toe)];",
        17,
        "expected the contact's kind, `six_d` or `point`, found `point(toe)` (a loop between \
         two frames goes in `loops: [name: point(a, b)]`)",
    );
    // A label where a list holds numbers is no number.
    check(
        &[B, J, "gravity: [x: 0.0, 0.0, -9.81];"],
        4,
        11,
        "expected a number, found `x: 0.0`",
    );
}

#[test]
fn contact_on_a_frame_that_cannot_move() {
    check_constraint(
        "contacts: [anchor: point];",
        12,
        "contact `anchor` holds a frame that cannot move (every joint between it and the world \
         is fixed or locked): its rows are zero, and `constrained_forward_dynamics` would refuse \
         them at every state; constrain a frame that moves",
    );
}

#[test]
fn more_constraint_rows_than_velocities() {
    check_constraint(
        "contacts: [tip: six_d, a: six_d];",
        24,
        "the constraints have 12 rows and `C` has 9 velocity coordinates: more rows than \
         velocities depend on each other at every state, which the exact solve of \
         `constrained_forward_dynamics` refuses; declare fewer constraints, or `point` contacts \
         (3 rows) for `six_d` ones (6)",
    );
}

#[test]
fn unknown_loop_kind() {
    check_constraint(
        "loops: [rod: line(tip, anchor)];",
        14,
        "unknown loop kind `line`: expected `point(a, b)` (frame `a`'s origin held on frame \
         `b`'s: 3 rows, a force in world axes) or `six_d(a, b)` (frame `a` held on frame `b`: 6 \
         rows, a wrench in `a`'s axes)",
    );
    check_constraint(
        "loops: [rod: pont(tip, anchor)];",
        14,
        "unknown loop kind `pont`: did you mean `point`? expected `point(a, b)` (frame `a`'s \
         origin held on frame `b`'s: 3 rows, a force in world axes) or `six_d(a, b)` (frame `a` \
         held on frame `b`: 6 rows, a wrench in `a`'s axes)",
    );
}

#[test]
fn loop_on_an_unknown_frame() {
    check_constraint(
        "loops: [rod: point(tip, anchr)];",
        25,
        "unknown frame `anchr`: did you mean `anchor`? expected a body or a frame of `C` (`a`, \
         `anchor`, `b`, `tip`, `toe`)",
    );
}

#[test]
fn loop_of_a_frame_on_itself() {
    check_constraint(
        "loops: [rod: point(tip, tip)];",
        25,
        "loop `rod` holds frame `tip` on itself: expected two different frames, `point(a, b)` \
         holding `a`'s origin on `b`'s",
    );
}

#[test]
fn loop_between_frames_of_one_body() {
    check_constraint(
        "loops: [rod: point(tip, toe)];",
        9,
        "loop `rod` holds frames `tip` and `toe`, fixed to the same body `b`: the distance \
         between them never changes, so the loop holds nothing and its rows depend on each \
         other at every state; close it between frames on bodies that move apart",
    );
}

#[test]
fn loop_declared_twice() {
    check_constraint(
        "loops: [rod: point(tip, anchor), rod: point(toe, anchor)];",
        34,
        "loop `rod` is declared twice in `loops`",
    );
}

#[test]
fn malformed_loops() {
    check_constraint(
        "loops: [point(tip, anchor)];",
        9,
        "expected a loop `name: point(a, b)` such as `rod: point(tip, ground)`, found \
         `point(tip, anchor)`",
    );
    check_constraint(
        "loops: [rod: point(tip)];",
        14,
        "expected the loop's two frames, `point(a, b)` (frame `a`'s origin held on frame \
         `b`'s), found 1 in `point(tip)`",
    );
    check_constraint(
        "loops: [rod: point(tip, 1.0)];",
        25,
        "expected a frame name, found `1.0`",
    );
    check_constraint(
        "loops: rod;",
        8,
        "expected a list of loops such as `[rod: point(tip, ground)]`, found `rod`",
    );
}

#[test]
fn contact_on_a_frame_already_reported_is_not_reported_again() {
    let mut items = vec!["contacts: [heel: point];"];
    items.extend(FREE);
    items.push("frame heel { parent: c }");
    check(
        &items,
        10,
        22,
        "unknown body `c` as parent of frame `heel`: expected `world` or a body (`a`, `b`)",
    );
}

/// `Builder::contacts` and `Builder::loops` state the constraints as the description does: what
/// they generate, and the check stage's problems with them, each one.
#[test]
fn a_builder_states_constraints() {
    use articulated_codegen::options::ContactKind;
    use articulated_codegen::Builder;
    let d = || parse_chain_str(&chain(&FREE), Path::new("free.chain")).unwrap();
    let source = Builder::new()
        .description(d())
        .contacts(&[("tip", ContactKind::SixD)])
        .loops(&[("rod", ContactKind::Point, "toe", "anchor")])
        .to_source()
        .unwrap_or_else(|e| panic!("{e}"));
    for expected in [
        "pub const CONSTRAINT_ROWS: usize = 9;",
        "pub fn constrained_forward_dynamics(",
        "const FRAMES: &'static [&'static str] = &[\"tip\", \"toe\", \"anchor\"];",
    ] {
        assert!(source.contains(expected), "no `{expected}` in:\n{source}");
    }
    let e = Builder::new()
        .description(d())
        .contacts(&[("tpi", ContactKind::Point)])
        .loops(&[("rod", ContactKind::Point, "tip", "tip")])
        .to_source()
        .unwrap_err()
        .to_string();
    let lines: Vec<&str> = e.lines().collect();
    assert_eq!(lines.len(), 2, "{e}");
    assert!(
        lines[0].starts_with("the model `C`: unknown frame `tpi`: did you mean `tip`?"),
        "{e}"
    );
    assert!(
        lines[1].starts_with("the model `C`: loop `rod` holds frame `tip` on itself"),
        "{e}"
    );
}
