//! The emitter: a 2-link planar mass matrix traced from code generic over `Scalar`, emitted,
//! formatted, read, and (in `emitted_code_builds_passes_clippy_and_matches_eval`) compiled in a
//! `#![no_std]` crate, linted with `clippy -D warnings`, run, and compared with the f64
//! interpretation of the graph and with the closed form.

// The tests feed the emitter constants such as 3.14 on purpose, to check that the code it writes
// for them passes this very lint.
#![allow(clippy::approx_constant)]

use std::path::{Path, PathBuf};
use std::process::Command;

use articulated_codegen::emit::{self, EmitError, Emitted};
use articulated_codegen::options::ScalarKind;
use articulated_codegen::sym::{trace, Graph, Sym, Var};
use articulated_dynamics::Scalar;
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

/// Lengths, centre-of-mass distances, masses and inertias of the two links.
const L1: f64 = 0.8;
const LC1: f64 = 0.35;
const LC2: f64 = 0.45;
const M1: f64 = 2.5;
const M2: f64 = 1.75;
const I1: f64 = 0.12;
const I2: f64 = 0.07;

/// Mass matrix of a planar two-link arm, M = Σ mᵢ Jᵢᵀ Jᵢ + [[I1+I2, I2], [I2, I2]], from the
/// centre-of-mass Jacobians (the way a tracer meets it, zeros and ones included). Generic over the
/// scalar, so the same code runs on `f64` and on `Sym`.
fn mass_matrix<T: Scalar>(q: [T; 2], name: impl Fn(T, &str) -> T) -> [[T; 2]; 2] {
    let k = T::from_f64;
    let (s1, c1) = q[0].sin_cos();
    let q12 = name(q[0] + q[1], "q12");
    let (s12, c12) = q12.sin_cos();
    // Jacobians of the centres of mass: rows x, y; columns q1, q2.
    let j1 = [[-k(LC1) * s1, T::zero()], [k(LC1) * c1, T::zero()]];
    let j2x = name(-k(L1) * s1 - k(LC2) * s12, "J2 x");
    let j2y = name(k(L1) * c1 + k(LC2) * c12, "J2 y");
    let j2 = [[j2x, -k(LC2) * s12], [j2y, k(LC2) * c12]];
    let rot = [[k(I1 + I2), k(I2)], [k(I2), k(I2)]];
    let mut m = [[T::zero(); 2]; 2];
    for r in 0..2 {
        for c in 0..2 {
            let mut acc = rot[r][c];
            for (mass, j) in [(k(M1), &j1), (k(M2), &j2)] {
                acc = acc + mass * (j[0][r] * j[0][c] + j[1][r] * j[1][c]);
            }
            m[r][c] = acc;
        }
    }
    m
}

/// The closed form, independent of the code above.
fn closed_form(q: [f64; 2]) -> [[f64; 2]; 2] {
    let c2 = q[1].cos();
    let m22 = M2 * LC2 * LC2 + I2;
    let m12 = M2 * (LC2 * LC2 + L1 * LC2 * c2) + I2;
    let m11 = M1 * LC1 * LC1 + I1 + M2 * (L1 * L1 + LC2 * LC2 + 2.0 * L1 * LC2 * c2) + I2;
    [[m11, m12], [m12, m22]]
}

fn traced() -> (Graph, Vec<Sym>) {
    let (graph, m) = trace(|| {
        let q = [Sym::input(Var::Q(0)), Sym::input(Var::Q(1))];
        mass_matrix(q, Sym::named)
    });
    // M is symmetric: the two off-diagonal entries are one node (hash-consing).
    assert_eq!(m[0][1], m[1][0]);
    (graph, vec![m[0][0], m[0][1], m[1][0], m[1][1]])
}

/// `q[i]` for input `Q(i)`.
fn q_input(v: Var) -> TokenStream {
    match v {
        Var::Q(i) => {
            let i = Literal::usize_unsuffixed(i);
            quote!(q[#i])
        }
        other => panic!("unexpected input {other:?}"),
    }
}

/// `fn name(q: &[ty; 2]) -> [[ty; 2]; 2]` (generic over `T` for `Generic`).
fn wrap(name: &str, scalar: ScalarKind, e: &Emitted) -> TokenStream {
    let name = format_ident!("{}", name);
    let Emitted {
        uses,
        statements,
        outputs,
        ..
    } = e;
    let [m00, m01, m10, m11] = [&outputs[0], &outputs[1], &outputs[2], &outputs[3]];
    let (generics, ty) = match scalar {
        ScalarKind::F64 => (quote!(), quote!(f64)),
        ScalarKind::F32 => (quote!(), quote!(f32)),
        ScalarKind::Generic => (
            quote!(<T: ::articulated::nalgebra::RealField + Copy>),
            quote!(T),
        ),
    };
    quote! {
        /// Mass matrix of the planar two-link arm (generated).
        pub fn #name #generics (q: &[#ty; 2]) -> [[#ty; 2]; 2] {
            #uses
            #statements
            [[#m00, #m01], [#m10, #m11]]
        }
    }
}

fn emitted(scalar: ScalarKind) -> (Graph, Vec<Sym>, Emitted) {
    let (graph, outputs) = traced();
    let e = emit::straight_line(&graph, &outputs, scalar, &q_input).expect("finite constants");
    (graph, outputs, e)
}

#[test]
fn the_traced_mass_matrix_evaluates_to_the_closed_form() {
    let (graph, outputs) = traced();
    for q in [[0.0, 0.0], [0.3, -1.2], [2.5, 0.7], [-3.0, 3.1]] {
        let m = graph.eval(&outputs, |v| match v {
            Var::Q(i) => q[i],
            _ => unreachable!(),
        });
        let expected = closed_form(q);
        for (k, (got, want)) in m.iter().zip(expected.iter().flatten()).enumerate() {
            approx::assert_relative_eq!(*got, *want, max_relative = 1e-13, epsilon = 1e-14);
            let _ = k;
        }
    }
}

#[test]
fn op_counts_of_the_mass_matrix() {
    let (_, _, e) = emitted(ScalarKind::F64);
    let ops = e.ops;
    // Two sin/cos pairs (q0 and q0+q1), nothing else transcendental.
    assert_eq!((ops.sin_cos, ops.sqrts, ops.divs), (2, 0, 0));
    println!("2-link mass matrix: {ops}");
    // Folding keeps it small: the naive loop above does 3·(2 + 2·3) = 24 adds and 3·2·3 = 18
    // multiplies for the three distinct entries, plus the Jacobians.
    assert!(ops.total() < 40, "{ops}");
}

#[test]
fn formatted_code_is_readable_and_has_no_folded_away_pattern() {
    for scalar in [ScalarKind::F64, ScalarKind::F32, ScalarKind::Generic] {
        let (_, _, e) = emitted(scalar);
        let text = emit::format(wrap("mass_matrix", scalar, &e)).unwrap();
        println!("{text}");
        // Names: sin/cos of an input and of a named node, hint names.
        for name in [
            "s_q0",
            "c_q0",
            "s_q12",
            "c_q12",
            "let q12 =",
            "j2_x",
            "j2_y",
        ] {
            assert!(text.contains(name), "{name} missing in\n{text}");
        }
        // One call for each sin/cos pair.
        let sincos = match scalar {
            ScalarKind::F64 => "::articulated::libm::sincos(",
            ScalarKind::F32 => "::articulated::libm::sincosf(",
            ScalarKind::Generic => ".sin_cos()",
        };
        assert_eq!(text.matches(sincos).count(), 2, "{text}");
        for bad in [
            "* 1.0", "1.0 *", "+ 0.0", "0.0 +", "- 0.0", "0.0 *", "* 0.0", "- -", "+ -", "--",
            "* -1.0", "-1.0 *", "(1.0)", "(0.0)", "(-1.0)", ".sin()", ".cos()", "::sin(", "::cos(",
            "::sinf(", "::cosf(",
        ] {
            assert!(!text.contains(bad), "`{bad}` in\n{text}");
        }
        // Every let is used later (no dead code, no copies `let a = b;`).
        for line in text.lines().filter(|l| l.trim_start().starts_with("let ")) {
            let rhs = line.split_once('=').unwrap().1.trim().trim_end_matches(';');
            assert!(
                !rhs.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.'),
                "copy or constant binding: {line}"
            );
        }
        // Literals per scalar.
        match scalar {
            ScalarKind::F64 => assert!(text.contains("_f64") && !text.contains("_f32")),
            ScalarKind::F32 => assert!(text.contains("_f32") && !text.contains("_f64")),
            ScalarKind::Generic => {
                assert!(text.contains("::articulated::nalgebra::convert::<f64, T>("))
            }
        }
    }
}

#[test]
fn names_avoid_inputs_keywords_and_each_other() {
    let (graph, out) = trace(|| {
        let q0 = Sym::input(Var::Q(0));
        let q1 = Sym::input(Var::Q(1));
        let a = (q0 * q1).named("q");
        let b = (q0 + q1).named("Type");
        let c = (q0 - q1).named("t0");
        let d = (q0 / q1).named("t0");
        let e = (a * b).named("élan 2");
        let f = (e * c).named("3 links");
        let g = (f * d).named("bodyFrame.r");
        vec![g, a * c]
    });
    let e = emit::straight_line(&graph, &out, ScalarKind::F64, &q_input).unwrap();
    let text = e.statements.to_string();
    for want in [
        "let q_2 =",
        "let type_2 =",
        "let t0 =",
        "let t0_2 =",
        "let lan_2 =",
        "let n_3_links =",
        "let body_frame_r =",
        "let t1 =",
    ] {
        assert!(text.contains(want), "{want} missing in {text}");
    }
    assert!(!text.contains("let q ="), "{text}");
}

#[test]
fn constants_round_trip_and_dodge_approx_constant() {
    let (graph, out) = trace(|| {
        let x = Sym::input(Var::Q(0));
        let k = Sym::from_f64;
        vec![
            k(3.14) * x,
            k(std::f64::consts::PI) * x,
            k(-std::f64::consts::FRAC_PI_2) * x,
            k(0.3183) * x,
            k(1e-7) * x,
            k(1.5e300) * x,
            k(0.1) * x,
            k(2.0),
            x,
        ]
    });
    let f64s = emit::straight_line(&graph, &out, ScalarKind::F64, &q_input).unwrap();
    let text = f64s.statements.to_string();
    for want in [
        "(314.0_f64 / 100.0_f64) * q [0]",
        ":: core :: f64 :: consts :: PI * q [0]",
        "- :: core :: f64 :: consts :: FRAC_PI_2 * q [0]",
        "(3183.0_f64 / 10000.0_f64) * q [0]",
        "1e-7_f64",
        "1.5e300_f64",
        "0.1_f64",
    ] {
        assert!(text.contains(want), "{want} missing in {text}");
    }
    let outputs: Vec<String> = f64s.outputs.iter().map(|o| o.to_string()).collect();
    assert_eq!(outputs[7], "2.0_f64");
    assert_eq!(outputs[8], "q [0]");
    // Every printed literal reads back as the constant in the graph.
    for tok in text.split_whitespace() {
        if let Some(digits) = tok.trim_matches(['(', ')']).strip_suffix("_f64") {
            let x: f64 = digits.parse().unwrap();
            assert!(
                [314.0, 100.0, 3183.0, 10000.0, 1e-7, 1.5e300, 0.1].contains(&x),
                "{tok}"
            );
        }
    }

    // 1.5e300 overflows f32.
    let err = emit::straight_line(&graph, &out, ScalarKind::F32, &q_input).unwrap_err();
    assert_eq!(
        err,
        EmitError::NonFiniteConstant {
            value: 1.5e300,
            scalar: ScalarKind::F32
        }
    );
    let generic = emit::straight_line(&graph, &out[..5], ScalarKind::Generic, &q_input).unwrap();
    assert!(generic
        .statements
        .to_string()
        .contains("convert :: < f64 , T > (314.0 / 100.0)"));
}

#[test]
fn f32_constants_that_round_to_zero_or_one_fold_away() {
    let (graph, out) = trace(|| {
        let (x, y) = (Sym::input(Var::Q(0)), Sym::input(Var::Q(1)));
        let k = Sym::from_f64;
        vec![
            k(1.0 + 1e-10) * x + k(1e-50) * y,
            k(-1.0 - 1e-12) * y.named("why"),
            k(0.1) * x,
            // Rounds to 0.5 and 2 in f32; their product, folded in f64, is 1 + 2e-12: rounds to 1.
            (k(0.5 + 1e-12) * k(2.0)) * y,
        ]
    });
    let e32 = emit::straight_line(&graph, &out, ScalarKind::F32, &q_input).unwrap();
    let outputs: Vec<String> = e32.outputs.iter().map(|o| o.to_string()).collect();
    assert_eq!(outputs[0], "q [0]");
    assert_eq!(outputs[3], "q [1]");
    let text = e32.statements.to_string();
    assert!(text.contains("= - q [1] ;"), "{text}");
    assert!(text.contains("0.1_f32 * q [0]"), "{text}");
    assert!(
        !text.contains("1.0_f32") && !text.contains("0.0_f32"),
        "{text}"
    );
    assert_eq!((e32.ops.negs, e32.ops.muls, e32.ops.total()), (1, 1, 2));
    // In f64 every constant stays.
    let e64 = emit::straight_line(&graph, &out, ScalarKind::F64, &q_input).unwrap();
    assert_eq!(e64.ops.muls, 5);
}

#[test]
fn a_non_finite_constant_is_an_error_not_code() {
    let (graph, out) = trace(|| vec![Sym::from_f64(f64::NAN) * Sym::input(Var::Q(0))]);
    let err = emit::straight_line(&graph, &out, ScalarKind::F64, &q_input).unwrap_err();
    assert!(matches!(err, EmitError::NonFiniteConstant { value, .. } if value.is_nan()));
    let syn_err: syn::Error = err.into();
    assert!(syn_err.to_string().contains("not a finite f64"));
}

#[test]
fn format_rejects_what_is_not_an_item_list() {
    assert!(emit::format(quote!(let x = 1;)).is_err());
    assert!(emit::format(quote!(
        fn f() {}
    ))
    .unwrap()
    .contains("fn f() {}"));
}

/// Writes a crate (and the `articulated` shim it depends on) under `/tmp`, runs `cargo build`,
/// `cargo clippy -D warnings` and then the binary with `args`, and returns its stdout.
fn build_lint_run(dir: &str, lib: &str, main: &str, nalgebra: bool, args: &[String]) -> String {
    let root = PathBuf::from("/tmp/articulated-emit-check").join(dir);
    let target = PathBuf::from("/tmp/articulated-emit-check/target");
    let write = |path: &Path, text: &str| {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        // Unchanged files keep their mtime, so cargo rebuilds nothing.
        if std::fs::read_to_string(path).ok().as_deref() != Some(text) {
            std::fs::write(path, text).unwrap();
        }
    };
    let (shim_dep, shim_use) = if nalgebra {
        (
            "nalgebra = { version = \"0.34\", default-features = false, features = [\"libm\"] }",
            "pub use nalgebra;",
        )
    } else {
        ("", "")
    };
    write(
        &root.join("articulated/Cargo.toml"),
        &format!(
            "[package]\nname = \"articulated\"\nversion = \"0.0.0\"\nedition = \"2021\"\n\n\
             [dependencies]\nlibm = \"0.2\"\n{shim_dep}\n"
        ),
    );
    write(
        &root.join("articulated/src/lib.rs"),
        &format!(
            "//! Stands in for the runtime's re-exports.\n#![no_std]\npub use libm;\n{shim_use}\n\
             /// Stands in for the runtime's `math`.\npub mod math {{\n\
             /// `a·b + c`, unfused, as the runtime's without FMA.\n\
             pub fn mul_add(a: f64, b: f64, c: f64) -> f64 {{ a * b + c }}\n\
             /// `a·b + c` in `f32`.\n\
             pub fn mul_addf(a: f32, b: f32, c: f32) -> f32 {{ a * b + c }}\n}}\n"
        ),
    );
    write(
        &root.join("Cargo.toml"),
        "[package]\nname = \"emit-check\"\nversion = \"0.0.0\"\nedition = \"2021\"\n\n\
         [dependencies]\narticulated = { path = \"articulated\" }\n\n[workspace]\n",
    );
    write(&root.join("src/lib.rs"), lib);
    write(&root.join("src/main.rs"), main);

    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let run = |args: &[&str]| {
        let out = Command::new(&cargo)
            .arg(args[0])
            .args(["--offline", "--quiet"])
            .args(&args[1..])
            .current_dir(&root)
            .env("CARGO_TARGET_DIR", &target)
            .env_remove("RUSTFLAGS")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "cargo {args:?} failed:\n{}\n{}\nin {}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr),
            root.display()
        );
        String::from_utf8(out.stdout).unwrap()
    };
    run(&["build"]);
    run(&["clippy", "--all-targets", "--", "-D", "warnings"]);
    let mut all = vec!["run", "--"];
    all.extend(args.iter().map(String::as_str));
    run(&all)
}

/// The lints the generated code must also pass, beyond clippy's defaults.
const LIB_HEADER: &str = "//! Emitted by `articulated-codegen`'s tests.\n\
    #![no_std]\n\
    #![forbid(unsafe_code)]\n\
    #![deny(clippy::panic, clippy::indexing_slicing, clippy::unwrap_used)]\n";

/// Parses the binary's output: one `f64` per whitespace-separated word.
fn numbers(text: &str) -> Vec<f64> {
    text.split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect()
}

#[test]
fn emitted_code_builds_passes_clippy_and_matches_eval() {
    let (graph, outputs, e64) = emitted(ScalarKind::F64);
    let (_, _, e32) = emitted(ScalarKind::F32);
    let items = {
        let f64s = wrap("mass_matrix", ScalarKind::F64, &e64);
        let f32s = wrap("mass_matrix_f32", ScalarKind::F32, &e32);
        // Constants that clippy's approx_constant, excessive_precision, … look at.
        let (cg, co) = trace(|| {
            let x = Sym::input(Var::Q(0));
            let k = Sym::from_f64;
            vec![
                k(3.14) * x,
                k(std::f64::consts::PI) * x,
                k(-std::f64::consts::FRAC_PI_2) * x,
                k(0.3183) * x - k(2.718) / x,
                k(1e-7) * x + k(1.0e20),
                k(0.1) * x,
                -x,
                (k(2.0) * x).sqrt(),
                x,
                k(1.5),
            ]
        });
        let ce = emit::straight_line(&cg, &co, ScalarKind::F64, &q_input).unwrap();
        let (cu, cs, cv) = (&ce.uses, &ce.statements, &ce.outputs);
        quote! {
            #f64s
            #f32s
            /// Constants (generated).
            pub fn constants(q: &[f64; 1]) -> [f64; 10] {
                #cu
                #cs
                [#(#cv),*]
            }
        }
    };
    let lib = format!("{LIB_HEADER}\n{}", emit::format(items).unwrap());
    let main = r#"//! Prints the generated functions' values at the q given on the command line.
fn main() {
    let q: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().unwrap()).collect();
    let m = emit_check::mass_matrix(&[q[0], q[1]]);
    let m32 = emit_check::mass_matrix_f32(&[q[0] as f32, q[1] as f32]);
    let k = emit_check::constants(&[q[0]]);
    for x in m.iter().flatten() {
        print!("{x:?} ");
    }
    for x in m32.iter().flatten() {
        print!("{:?} ", f64::from(*x));
    }
    for x in k {
        print!("{x:?} ");
    }
    println!();
}
"#;
    let q = [0.3_f64, -1.2_f64];
    let args: Vec<String> = q.iter().map(|x| format!("{x:?}")).collect();
    let started = std::time::Instant::now();
    let out = numbers(&build_lint_run("f64-f32", &lib, main, false, &args));
    println!("built, linted and ran in {:?}", started.elapsed());

    let eval = graph.eval(&outputs, |v| match v {
        Var::Q(i) => q[i],
        _ => unreachable!(),
    });
    // f64: the same operations in the same order with the same libm: bit for bit.
    assert_eq!(&out[0..4], &eval[..], "f64 code vs graph eval");
    // f32: close.
    for (a, b) in out[4..8].iter().zip(&eval) {
        approx::assert_relative_eq!(*a, *b, max_relative = 1e-5);
    }
    // Closed form, independently.
    for (a, b) in out[0..4].iter().zip(closed_form(q).iter().flatten()) {
        approx::assert_relative_eq!(*a, *b, max_relative = 1e-13);
    }
    // Constants.
    let x = q[0];
    let pi = std::f64::consts::PI;
    let expected = [
        3.14 * x,
        pi * x,
        -std::f64::consts::FRAC_PI_2 * x,
        0.3183 * x - 2.718 / x,
        1e-7 * x + 1.0e20,
        0.1 * x,
        -x,
        (2.0 * x).sqrt(),
        x,
        1.5,
    ];
    assert_eq!(&out[8..], &expected[..]);
}

#[test]
#[ignore = "builds nalgebra in a scratch crate (about a minute on a 2-core machine the first time)"]
fn generic_emitted_code_builds_passes_clippy_and_matches_eval() {
    let (graph, outputs, e) = emitted(ScalarKind::Generic);
    let items = wrap("mass_matrix", ScalarKind::Generic, &e);
    let lib = format!("{LIB_HEADER}\n{}", emit::format(items).unwrap());
    let main = r#"//! Prints the generated function's value at the q given on the command line.
fn main() {
    let q: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().unwrap()).collect();
    let m = emit_check::mass_matrix::<f64>(&[q[0], q[1]]);
    for x in m.iter().flatten() {
        print!("{x:?} ");
    }
    println!();
}
"#;
    let q = [2.5_f64, 0.7_f64];
    let args: Vec<String> = q.iter().map(|x| format!("{x:?}")).collect();
    let out = numbers(&build_lint_run("generic", &lib, main, true, &args));
    let eval = graph.eval(&outputs, |v| match v {
        Var::Q(i) => q[i],
        _ => unreachable!(),
    });
    for (a, b) in out.iter().zip(&eval) {
        approx::assert_relative_eq!(*a, *b, max_relative = 1e-14);
    }
}
