//! From a [`Model`] to Rust: trace each requested output's recursion over the symbolic scalar
//! ([`crate::sym`]), emit it as straight-line code ([`crate::emit`]), and wrap it in the type and
//! trait impls the runtime defines (`articulated::{Chain, MassMatrix, Bias, Gravity,
//! InverseDynamics, ForwardDynamics}`, DESIGN §4).
//!
//! The recursions traced are the reference's own generic code (`articulated_dynamics::reference`:
//! RNEA, CRBA, ABA), instantiated on [`Sym`]: what the reference computes in `f64` at run time,
//! the generator records once, folds and emits. The reference's independence comes from its own
//! checks (Wieber's second formulation, closed forms, Pinocchio).
//!
//! Forward dynamics is traced two ways and the one with fewer operations is kept, per model:
//! - **ABA** (Featherstone 2008, RBDA §7.3), O(n);
//! - **CRBA + LᵀDL**: `M` from CRBA, `h = N·q̇ + g` from RNEA, then `M = LᵀDL` factored from the
//!   last coordinate to the first (RBDA §6.5, "LTDL"), which keeps the tree's sparsity: the
//!   structural zeros of `M` are exact zeros in the graph, so every product with them folds away.

use articulated_dynamics::model::{JointKind, Model};
use articulated_dynamics::reference::{aba, crba, rnea, Tree};
use articulated_dynamics::Scalar;
use proc_macro2::{Ident, Span, TokenStream};
use quote::{format_ident, quote};

use crate::emit::{self, Emitted};
use crate::newton_euler::classical_rnea;
use crate::options::{Options, Output, ScalarKind};
use crate::reassociate::reassociate;
use crate::regroup::{coordinate_axis, regroup};
use crate::sym::{self, Graph, OpCounts, Sym, Var};

/// Relative pivot tolerance of generated forward dynamics: a pivot must exceed this fraction of
/// its unreduced value (the same test as the reference's ABA, `articulated::reference`).
const PIVOT_TOL_F64: f64 = 1e-13;
/// The same for `f32` (its epsilon is 1.2e-7).
const PIVOT_TOL_F32: f64 = 1e-6;
/// Every pivot must also exceed this fraction of the sum of all unreduced pivots (for CRBA +
/// LᵀDL, the trace of `M`). A pivot of an exactly singular `M` comes out as rounding noise, about
/// ε·trace(M) times some growth, which can pass the test against its own unreduced value (a
/// massless root under a free base: the pivot of 1e-16 against `M_kk` of 1e-3); against the
/// trace it cannot. Legitimate pivots of ill-conditioned chains (κ up to 1e11) pass.
const PIVOT_TOL_GLOBAL_F64: f64 = 1e-12;
/// The same for `f32`.
const PIVOT_TOL_GLOBAL_F32: f64 = 1e-5;

/// How forward dynamics is computed in generated code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FdMethod {
    /// The articulated-body algorithm.
    Aba,
    /// CRBA, RNEA, then a sparse `LᵀDL` of `M` and two triangular solves.
    CrbaLtdl,
}

impl FdMethod {
    /// A short name for docs and reports.
    pub fn name(self) -> &'static str {
        match self {
            FdMethod::Aba => "ABA (RBDA §7.3)",
            FdMethod::CrbaLtdl => "CRBA + sparse LᵀDL (RBDA §6.2, §6.5)",
        }
    }
}

/// One output traced into its own graph.
#[derive(Debug)]
pub struct Traced {
    /// Which output.
    pub output: Output,
    /// The expression graph.
    pub graph: Graph,
    /// The values, in order: `M` row-major for the mass matrix, one per velocity otherwise.
    pub values: Vec<Sym>,
    /// Forward dynamics only: each pivot with the unreduced value it is compared to.
    pub pivots: Vec<(Sym, Sym)>,
    /// Forward dynamics only: the sum of the unreduced values, which every pivot is compared
    /// to as well.
    pub scale: Option<Sym>,
    /// Forward dynamics only: the method kept.
    pub method: Option<FdMethod>,
    /// Forward dynamics only: the operation counts of both methods (ABA, CRBA + LᵀDL).
    pub candidates: Vec<(FdMethod, OpCounts)>,
    /// Whether the inertias were regrouped first ([`crate::regroup`]).
    pub regrouped: bool,
    /// The recursion traced.
    pub formulation: Formulation,
}

impl Traced {
    /// Operations the emitted function performs (values and pivots).
    pub fn ops(&self) -> OpCounts {
        self.graph.op_counts(&self.all_outputs())
    }

    fn all_outputs(&self) -> Vec<Sym> {
        let mut all = self.values.clone();
        for (p, d) in &self.pivots {
            all.push(*p);
            all.push(*d);
        }
        all.extend(self.scale);
        all
    }

    /// The same values with every sum regrouped so that late terms are added last
    /// ([`crate::reassociate`]): no more operations, a shorter critical path.
    fn reassociated(self) -> Traced {
        let all = self.all_outputs();
        let (graph, mut new) = reassociate(&self.graph, &all);
        let scale = self.scale.map(|_| new.pop().expect("the scale"));
        let pivots = new.split_off(self.values.len());
        Traced {
            graph,
            values: new,
            pivots: pivots.chunks(2).map(|pd| (pd[0], pd[1])).collect(),
            scale,
            ..self
        }
    }

    /// Evaluates the graph in `f64` (the CLI's `--engine symbolic`): the values, then, for
    /// forward dynamics, whether every pivot passed.
    pub fn eval(&self, input: impl Fn(Var) -> f64) -> (Vec<f64>, bool) {
        let all = self.graph.eval(&self.all_outputs(), input);
        let (values, rest) = all.split_at(self.values.len());
        let (pivots, scale) = rest.split_at(2 * self.pivots.len());
        let scale = scale.first().copied().unwrap_or(0.0);
        let ok = pivots.chunks(2).all(|pd| {
            pd[0] > PIVOT_TOL_F64 * pd[1]
                && pd[0] > PIVOT_TOL_GLOBAL_F64 * scale
                && pd[0].is_finite()
        });
        (values.to_vec(), ok)
    }
}

/// Names each body's transform from its parent (`X_up`: rotation `{body}_e{i}{j}`, translation
/// `{body}_r{i}`) so the emitted code reads in body terms. The recursions compute the same
/// transforms later; hash-consing makes them these very nodes, so the names stick.
fn name_bodies(model: &Model, tree: &Tree<Sym>, q: &[Sym]) {
    let x_up = tree.x_up(q);
    for (b, body) in model.bodies.iter().enumerate() {
        let x = &x_up[tree.body_node[b]];
        for i in 0..3 {
            for j in 0..3 {
                x.e.0[i][j].named(&format!("{}_e{i}{j}", body.name));
            }
            x.r.0[i].named(&format!("{}_r{i}", body.name));
        }
    }
}

fn inputs(n: usize, var: fn(usize) -> Var) -> Vec<Sym> {
    (0..n).map(|i| Sym::input(var(i))).collect()
}

/// A recursion to trace on a tree, by a Newton–Euler formulation where that applies.
type TraceFn<'a> = dyn Fn(&Tree<Sym>, Formulation) -> Vec<Sym> + 'a;

/// Traces `output` of `model` into a graph.
pub fn trace(model: &Model, output: Output) -> Traced {
    trace_unordered(model, output).reassociated()
}

/// [`trace`] before the sums are regrouped by arrival time.
fn trace_unordered(model: &Model, output: Output) -> Traced {
    let (nq, nv, np) = (model.nq(), model.nv(), model.params.len());
    // Traced on the tree as described and on the regrouped tree, and for the outputs of
    // inverse dynamics by both Newton–Euler formulations; the one with fewer operations is kept.
    let simple = |forms: &[Formulation], f: &TraceFn| {
        let one = |regrouped: bool, form: Formulation| {
            let (graph, values) = sym::trace(|| {
                let params = inputs(np, Var::Param);
                let mut tree = Tree::new(model, &params);
                name_bodies(model, &tree, &inputs(nq, Var::Q));
                if regrouped {
                    regroup(&mut tree);
                }
                f(&tree, form)
            });
            Traced {
                output,
                graph,
                values,
                pivots: Vec::new(),
                scale: None,
                method: None,
                candidates: Vec::new(),
                regrouped,
                formulation: form,
            }
        };
        let all = forms
            .iter()
            .flat_map(|&form| [one(false, form), one(true, form)]);
        fewest(all)
    };
    let zeros = || vec![Sym::zero(); nv];
    let both = [Formulation::Reference, Formulation::Specialized];
    let (q, v, a) = (
        || inputs(nq, Var::Q),
        || inputs(nv, Var::V),
        || inputs(nv, Var::A),
    );
    match output {
        Output::MassMatrix => simple(&both, &|t, f| crba_by(f, t, &q())),
        Output::Bias => simple(&both, &|t, f| rnea_by(f, t, &q(), &v(), &zeros(), false)),
        Output::Gravity => simple(&both, &|t, f| rnea_by(f, t, &q(), &zeros(), &zeros(), true)),
        Output::InverseDynamics => simple(&both, &|t, f| rnea_by(f, t, &q(), &v(), &a(), true)),
        Output::ForwardDynamics => {
            // Each method on the tree as described and regrouped (and CRBA + LᵀDL with `h` by
            // both Newton–Euler formulations), the fewest operations kept.
            let by_aba = fewest(
                [false, true].map(|g| trace_fd(model, FdMethod::Aba, g, Formulation::Reference)),
            );
            let by_ltdl = fewest(
                [false, true]
                    .into_iter()
                    .flat_map(|g| both.map(|f| trace_fd(model, FdMethod::CrbaLtdl, g, f))),
            );
            let candidates = vec![
                (FdMethod::Aba, by_aba.ops()),
                (FdMethod::CrbaLtdl, by_ltdl.ops()),
            ];
            let mut best = if by_ltdl.ops().total() < by_aba.ops().total() {
                by_ltdl
            } else {
                by_aba
            };
            best.candidates = candidates;
            best
        }
    }
}

/// The candidate with the fewest operations (the first of equals).
fn fewest(candidates: impl IntoIterator<Item = Traced>) -> Traced {
    candidates
        .into_iter()
        .reduce(|best, t| {
            if t.ops().total() < best.ops().total() {
                t
            } else {
                best
            }
        })
        .expect("at least one candidate")
}

/// Which code the generator traces for an output: the reference's recursion, or the one
/// written for the generator that computes the same values in fewer operations (each output
/// keeps whichever of the two gives fewer).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    /// The reference's own recursion (spatial RNEA, CRBA, ABA).
    Reference,
    /// For `M`: [`crate::crba`] (symmetric composite inertias, double angles); for bias,
    /// gravity and inverse dynamics (and `h` in forward dynamics):
    /// [`crate::newton_euler`] (classical accelerations).
    Specialized,
}

/// Inverse dynamics by `form`.
fn rnea_by(
    form: Formulation,
    tree: &Tree<Sym>,
    q: &[Sym],
    v: &[Sym],
    a: &[Sym],
    g: bool,
) -> Vec<Sym> {
    match form {
        Formulation::Specialized => classical_rnea(tree, q, v, a, g),
        Formulation::Reference => rnea(tree, q, v, a, g),
    }
}

/// `M(q)` by `form`.
fn crba_by(form: Formulation, tree: &Tree<Sym>, q: &[Sym]) -> Vec<Sym> {
    match form {
        Formulation::Specialized => crate::crba::crba(tree, q, coordinate_axis),
        Formulation::Reference => crba(tree, q),
    }
}

/// Forward dynamics traced by `method`, on the regrouped tree if `regrouped`, with `h` (for
/// CRBA + LᵀDL) by the Newton–Euler formulation `form`. Regrouping
/// changes neither `M` nor ABA's pivots: every moved part `I_s` has `I_s·S = 0`, so each
/// `D_i = Sᵢᵀ·I^A_i·S_i` and `U_i = I^A_i·S_i` is the same.
fn trace_fd(model: &Model, method: FdMethod, regrouped: bool, form: Formulation) -> Traced {
    let (nq, nv, np) = (model.nq(), model.nv(), model.params.len());
    let (graph, (values, pivots, scale)) = sym::trace(|| {
        let params = inputs(np, Var::Param);
        let mut tree = Tree::new(model, &params);
        let (q, v, tau) = (inputs(nq, Var::Q), inputs(nv, Var::V), inputs(nv, Var::Tau));
        name_bodies(model, &tree, &q);
        if regrouped {
            regroup(&mut tree);
        }
        let (values, pivots) = match method {
            FdMethod::Aba => {
                let out = aba(&tree, &q, &v, &tau, true);
                (
                    out.qdd,
                    out.pivots.into_iter().zip(out.diag).collect::<Vec<_>>(),
                )
            }
            FdMethod::CrbaLtdl => {
                let m = crba_by(form, &tree, &q);
                let h = rnea_by(form, &tree, &q, &v, &vec![Sym::zero(); nv], true);
                let b: Vec<Sym> = tau.iter().zip(&h).map(|(&t, &h)| t - h).collect();
                ltdl_solve(m, b, nv)
            }
        };
        // Inside the trace: the sum is recorded in this graph.
        let scale = pivots.iter().map(|p| p.1).reduce(|a, b| a + b);
        (values, pivots, scale)
    });
    Traced {
        output: Output::ForwardDynamics,
        graph,
        values,
        scale,
        pivots,
        method: Some(method),
        candidates: Vec::new(),
        regrouped,
        formulation: form,
    }
}

/// Solves `M·x = b` by `M = LᵀDL`, eliminating from the last coordinate to the first
/// (Featherstone 2008, RBDA §6.5): in depth-first coordinate order a coordinate's descendants
/// come after it, so this order causes no fill-in on a tree. `m` is row-major `n × n`.
/// Returns `x` and each pivot `D_k` with the unreduced `M_kk`.
fn ltdl_solve<T: Scalar>(mut m: Vec<T>, b: Vec<T>, n: usize) -> (Vec<T>, Vec<(T, T)>) {
    let unreduced: Vec<T> = (0..n).map(|k| m[k * n + k]).collect();
    for k in (0..n).rev() {
        let d = m[k * n + k];
        // `i` descends, as in RBDA Table 6.3: row k's entries left of `i` are still unscaled
        // when the update of row `i` reads them.
        for i in (0..k).rev() {
            let a = m[k * n + i] / d;
            for j in 0..=i {
                m[i * n + j] = m[i * n + j] - m[k * n + j] * a;
            }
            m[k * n + i] = a;
        }
    }
    // Lᵀ·z = b (upper triangular), from the last coordinate up.
    let mut x = b;
    for k in (0..n).rev() {
        for i in 0..k {
            x[i] = x[i] - m[k * n + i] * x[k];
        }
    }
    // D·y = z.
    for (k, xk) in x.iter_mut().enumerate() {
        *xk = *xk / m[k * n + k];
    }
    // L·x = y, from the first coordinate down.
    for k in 0..n {
        for i in 0..k {
            x[k] = x[k] - m[k * n + i] * x[i];
        }
    }
    let pivots = (0..n).map(|k| (m[k * n + k], unreduced[k])).collect();
    (x, pivots)
}

/// What [`generate`] produced: the tokens and, per function, its operation counts.
#[derive(Debug)]
pub struct Generated {
    /// The type and its impls.
    pub tokens: TokenStream,
    /// Each emitted function: its output, operation counts and (forward dynamics) the method
    /// kept and both candidates' counts.
    pub functions: Vec<FunctionReport>,
}

/// One generated function's figures.
#[derive(Clone, Debug)]
pub struct FunctionReport {
    /// Which output.
    pub output: Output,
    /// Operations it performs.
    pub ops: OpCounts,
    /// Forward dynamics: the method kept.
    pub method: Option<FdMethod>,
    /// Forward dynamics: both candidates' counts.
    pub candidates: Vec<(FdMethod, OpCounts)>,
}

/// The runtime's `Coordinates` of a joint kind; `None` for a fixed joint.
fn coordinates_tokens(kind: JointKind) -> Option<TokenStream> {
    Some(match kind {
        JointKind::Fixed => return None,
        JointKind::SphericalQuaternion => quote!(::articulated::Coordinates::Quaternion),
        JointKind::FreeQuaternion => quote!(::articulated::Coordinates::FreeQuaternion),
        other => {
            let n = proc_macro2::Literal::usize_unsuffixed(other.nq());
            quote!(::articulated::Coordinates::Vector(#n))
        }
    })
}

/// The scalar type's tokens.
fn scalar_tokens(kind: ScalarKind) -> TokenStream {
    match kind {
        ScalarKind::F64 => quote!(f64),
        ScalarKind::F32 => quote!(f32),
        ScalarKind::Generic => quote!(T),
    }
}

fn ops_tokens(ops: &OpCounts) -> TokenStream {
    let OpCounts {
        adds,
        muls,
        divs,
        negs,
        sin_cos,
        sqrts,
    } = *ops;
    let [adds, muls, divs, negs, sin_cos, sqrts] =
        [adds, muls, divs, negs, sin_cos, sqrts].map(proc_macro2::Literal::usize_unsuffixed);
    quote! {
        ::articulated::OpCounts {
            adds: #adds, muls: #muls, divs: #divs, negs: #negs, sin_cos: #sin_cos, sqrts: #sqrts,
        }
    }
}

/// `let [[q0, _, q2]] = q.data.0;` binding the inputs a function uses (`_` for the others, so
/// the user's crate sees no unused variable).
fn destructure(vector: &Ident, n: usize, used: &[bool]) -> TokenStream {
    let names = (0..n).map(|i| {
        if used[i] {
            let id = format_ident!("{}{}", vector, i);
            quote!(#id)
        } else {
            quote!(_)
        }
    });
    quote! { let [[#(#names),*]] = #vector.data.0; }
}

fn var_ident(var: Var, params: &[Ident]) -> TokenStream {
    match var {
        Var::Q(i) => {
            let id = format_ident!("q{}", i);
            quote!(#id)
        }
        Var::V(i) => {
            let id = format_ident!("v{}", i);
            quote!(#id)
        }
        Var::A(i) => {
            let id = format_ident!("a{}", i);
            quote!(#id)
        }
        Var::Tau(i) => {
            let id = format_ident!("tau{}", i);
            quote!(#id)
        }
        Var::Param(i) => {
            let id = &params[i];
            quote!(p.#id)
        }
    }
}

/// Which inputs the live part of a graph reads, per kind.
struct Used {
    q: Vec<bool>,
    v: Vec<bool>,
    a: Vec<bool>,
    tau: Vec<bool>,
    params: bool,
}

fn used_inputs(t: &Traced, nq: usize, nv: usize) -> Used {
    let mut u = Used {
        q: vec![false; nq],
        v: vec![false; nv],
        a: vec![false; nv],
        tau: vec![false; nv],
        params: false,
    };
    for s in t.graph.live(&t.all_outputs()) {
        if let sym::Node::Input(var) = t.graph.node(s) {
            match var {
                Var::Q(i) => u.q[i] = true,
                Var::V(i) => u.v[i] = true,
                Var::A(i) => u.a[i] = true,
                Var::Tau(i) => u.tau[i] = true,
                Var::Param(_) => u.params = true,
            }
        }
    }
    u
}

/// Generates the type and trait impls for `model` (its `outputs`, in its `scalar`).
///
/// # Errors
/// A `syn::Error` at the call site for an output the generator does not produce yet, or a
/// constant that cannot be emitted.
pub fn generate(model: &Model, options: &Options) -> syn::Result<Generated> {
    generate_with(model, options, true)
}

/// [`generate`] without the struct itself, for `#[derive(Chain)]`, where the user wrote it.
///
/// # Errors
/// As [`generate`].
pub fn generate_impls(model: &Model, options: &Options) -> syn::Result<Generated> {
    generate_with(model, options, false)
}

fn generate_with(model: &Model, options: &Options, with_struct: bool) -> syn::Result<Generated> {
    let name = Ident::new(&model.name, Span::call_site());
    let name_str = &model.name;
    let vis = options.visibility.to_tokens();
    let (nq_n, nv_n) = (model.nq(), model.nv());
    let (nq, nv) = (
        proc_macro2::Literal::usize_unsuffixed(nq_n),
        proc_macro2::Literal::usize_unsuffixed(nv_n),
    );
    let scalar = scalar_tokens(options.scalar);
    let generic = options.scalar == ScalarKind::Generic;
    let param_idents: Vec<Ident> = model
        .params
        .iter()
        .map(|p| Ident::new(&p.name, Span::call_site()))
        .collect();
    let params_name = format_ident!("{}Params", name);
    let params_ty = match (param_idents.is_empty(), generic) {
        (true, _) => quote!(()),
        (false, true) => quote!(#params_name<T>),
        (false, false) => quote!(#params_name),
    };
    let impl_generics = if generic {
        quote!(<T: ::articulated::nalgebra::RealField + Copy>)
    } else {
        quote!()
    };
    // A literal as a person writes it: `1e-13_f64`, `2.5_f32` (the shortest digits that read
    // back exactly, which is what `{:?}` prints); tolerances and parameter defaults only, all
    // finite (the model was checked).
    let lit = |x: f64| -> TokenStream {
        let suffixed = |text: String| -> TokenStream {
            text.parse()
                .unwrap_or_else(|_| quote!(compile_error!("articulated: bad literal")))
        };
        match options.scalar {
            ScalarKind::F64 => suffixed(format!("{x:?}_f64")),
            ScalarKind::F32 => suffixed(format!("{:?}_f32", x as f32)),
            ScalarKind::Generic => {
                let l = suffixed(format!("{x:?}_f64"));
                quote!(::articulated::nalgebra::convert::<f64, T>(#l))
            }
        }
    };

    // Docs of the type: the user's, then what was generated.
    // Doc lines as `///` writes them, with a leading space (a URDF's or a program's may lack it).
    let user_doc = options.doc.iter().map(|d| {
        let d = if d.is_empty() || d.starts_with(' ') {
            d.clone()
        } else {
            format!(" {d}")
        };
        quote!(#[doc = #d])
    });
    let mut items = Vec::new();
    let mut consts = Vec::new();
    let mut functions = Vec::new();
    for &output in &options.outputs {
        let traced = trace(model, output);
        let ops = traced.ops();
        let used = used_inputs(&traced, nq_n, nv_n);
        let input = |var: Var| var_ident(var, &param_idents);
        let all = traced.all_outputs();
        let Emitted {
            statements,
            outputs,
            ..
        } = emit::straight_line(&traced.graph, &all, options.scalar, &input)?;
        let (values, pivot_exprs) = outputs.split_at(traced.values.len());
        let q_id = format_ident!("q");
        let v_id = format_ident!("v");
        let a_id = format_ident!("a");
        let tau_id = format_ident!("tau");
        let dq = destructure(&q_id, nq_n, &used.q);
        let p_arg = if used.params { quote!(p) } else { quote!(_p) };
        let vector = |vals: &[TokenStream]| {
            quote! {
                ::articulated::nalgebra::SVector::<#scalar, #nv>::from_array_storage(
                    ::articulated::nalgebra::ArrayStorage([[#(#vals),*]])
                )
            }
        };
        let mut ops_doc = format!(" Operations: {ops}.");
        if traced.formulation == Formulation::Specialized {
            if matches!(output, Output::MassMatrix | Output::ForwardDynamics) {
                ops_doc += " `M` by CRBA with the composite inertias carried up by their upper \
                            triangle and, through revolute joints about a coordinate axis, by \
                            double angles (`articulated_codegen::crba`).";
            }
            if output != Output::MassMatrix {
                ops_doc += " By Newton–Euler on classical accelerations (Khalil & Kleinfinger \
                            1987; `articulated_codegen::newton_euler`).";
            }
            ops_doc += " Fewer operations than the reference's recursion, the same values.";
        }
        if traced.regrouped {
            ops_doc += " Inertial parameters regrouped first (each body's mass, and the inertia \
                        its joint cannot move, carried by its parent; the same result with fewer \
                        terms: `articulated_codegen::regroup`).";
        }
        ops_doc += " Sums regrouped so that late terms are added last \
                    (`articulated_codegen::reassociate`).";
        if !generic {
            ops_doc += " A product added once is fused into its sum with `math::mul_add`: one \
                        FMA instruction where the target has it (`-C target-cpu=x86-64-v3` or \
                        newer), the product and the sum otherwise.";
        }
        let const_name = format_ident!("{}_OPS", output.name().to_uppercase());
        let const_doc = format!(" Operation count of `{}`: {ops}.", output.name());
        let ops_value = ops_tokens(&ops);
        consts.push(quote! { #[doc = #const_doc] pub const #const_name: ::articulated::OpCounts = #ops_value; });
        let sv = |n: &proc_macro2::Literal| quote!(::articulated::nalgebra::SVector<#scalar, #n>);
        let (sq, svv) = (sv(&nq), sv(&nv));
        let item = match output {
            Output::MassMatrix => {
                // nalgebra stores columns: column j is M[.][j]; M is symmetric, so row-major
                // entries read as columns give the same matrix.
                let cols = (0..nv_n).map(|j| {
                    let col = (0..nv_n).map(|i| &values[j * nv_n + i]);
                    quote!([#(#col),*])
                });
                quote! {
                    impl #impl_generics ::articulated::MassMatrix<#scalar, #nq, #nv> for #name {
                        #[doc = " `M(q)`, the joint-space mass matrix (CRBA, Featherstone 2008, RBDA §6.2)."]
                        #[doc = #ops_doc]
                        fn mass_matrix_with(q: &#sq, #p_arg: &#params_ty) -> ::articulated::nalgebra::SMatrix<#scalar, #nv, #nv> {
                            #dq
                            #statements
                            ::articulated::nalgebra::SMatrix::<#scalar, #nv, #nv>::from_array_storage(
                                ::articulated::nalgebra::ArrayStorage([#(#cols),*])
                            )
                        }
                    }
                }
            }
            Output::Bias => {
                let dv = destructure(&v_id, nv_n, &used.v);
                let out = vector(values);
                quote! {
                    impl #impl_generics ::articulated::Bias<#scalar, #nq, #nv> for #name {
                        #[doc = " `N(q, q̇)·q̇`, the velocity-product terms without gravity (RNEA with `a = 0` and no gravity, RBDA §5.3)."]
                        #[doc = #ops_doc]
                        fn bias_with(q: &#sq, v: &#svv, #p_arg: &#params_ty) -> #svv {
                            #dq
                            #dv
                            #statements
                            #out
                        }
                    }
                }
            }
            Output::Gravity => {
                let out = vector(values);
                quote! {
                    impl #impl_generics ::articulated::Gravity<#scalar, #nq, #nv> for #name {
                        #[doc = " `g(q)`, the generalized force that holds the chain still (RNEA with `v = a = 0`, RBDA §5.3)."]
                        #[doc = #ops_doc]
                        fn gravity_with(q: &#sq, #p_arg: &#params_ty) -> #svv {
                            #dq
                            #statements
                            #out
                        }
                    }
                }
            }
            Output::InverseDynamics => {
                let dv = destructure(&v_id, nv_n, &used.v);
                let da = destructure(&a_id, nv_n, &used.a);
                let out = vector(values);
                quote! {
                    impl #impl_generics ::articulated::InverseDynamics<#scalar, #nq, #nv> for #name {
                        #[doc = " `τ = M(q)·a + N(q, q̇)·q̇ + g(q)` (RNEA, Featherstone 2008, RBDA §5.3)."]
                        #[doc = #ops_doc]
                        fn inverse_dynamics_with(q: &#sq, v: &#svv, a: &#svv, #p_arg: &#params_ty) -> #svv {
                            #dq
                            #dv
                            #da
                            #statements
                            #out
                        }
                    }
                }
            }
            Output::ForwardDynamics => {
                let dv = destructure(&v_id, nv_n, &used.v);
                let dt = destructure(&tau_id, nv_n, &used.tau);
                let f32 = options.scalar == ScalarKind::F32;
                let tol = lit(if f32 { PIVOT_TOL_F32 } else { PIVOT_TOL_F64 });
                let tol_global = lit(if f32 {
                    PIVOT_TOL_GLOBAL_F32
                } else {
                    PIVOT_TOL_GLOBAL_F64
                });
                let (pairs, scale) = pivot_exprs.split_at(2 * traced.pivots.len());
                let scale = scale.first().cloned().unwrap_or_else(|| lit(0.0));
                let checks = pairs.chunks(2).enumerate().map(|(k, pd)| {
                    let (p, d) = (&pd[0], &pd[1]);
                    let k = proc_macro2::Literal::usize_unsuffixed(k);
                    quote! {
                        if !(::articulated::__private::positive_pivot(#p, #d, #tol)
                            && ::articulated::__private::positive_pivot(#p, #scale, #tol_global))
                        {
                            return Err(::articulated::SingularMassMatrix { velocity: #k });
                        }
                    }
                });
                let finite = values.iter().enumerate().map(|(k, x)| {
                    let k = proc_macro2::Literal::usize_unsuffixed(k);
                    quote! {
                        if !#x.is_finite() {
                            return Err(::articulated::SingularMassMatrix { velocity: #k });
                        }
                    }
                });
                let out = vector(values);
                let method_doc = format!(
                    " Computed by {} (the candidate with fewer operations for this chain: {}).",
                    traced.method.map_or("", FdMethod::name),
                    traced
                        .candidates
                        .iter()
                        .map(|(m, o)| format!("{} {}", m.name(), o.total()))
                        .collect::<Vec<_>>()
                        .join(", ")
                );
                quote! {
                    impl #impl_generics ::articulated::ForwardDynamics<#scalar, #nq, #nv> for #name {
                        #[doc = " `q̈ = M(q)⁻¹·(τ − N(q, q̇)·q̇ − g(q))`; an error where `M(q)` is singular."]
                        #[doc = #method_doc]
                        #[doc = #ops_doc]
                        fn forward_dynamics_with(q: &#sq, v: &#svv, tau: &#svv, #p_arg: &#params_ty)
                            -> ::core::result::Result<#svv, ::articulated::SingularMassMatrix> {
                            #dq
                            #dv
                            #dt
                            #statements
                            #(#checks)*
                            #(#finite)*
                            Ok(#out)
                        }
                    }
                }
            }
        };
        items.push(item);
        functions.push(FunctionReport {
            output,
            ops,
            method: traced.method,
            candidates: traced.candidates.clone(),
        });
    }

    let summary = format!(
        " Generated by `articulated` from the chain `{name_str}`: {} bodies, `NQ = {nq}` positions, \
         `NV = {nv}` velocities. Outputs: {}.",
        model.nb(),
        options
            .outputs
            .iter()
            .map(|o| format!("`{}`", o.name()))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let params_item = if param_idents.is_empty() {
        quote!()
    } else {
        let fields = model.params.iter().zip(&param_idents).map(|(p, id)| {
            let d = format!(" `{}` (default {:?}).", p.name, p.default);
            quote! { #[doc = #d] pub #id: #scalar, }
        });
        let defaults = model.params.iter().zip(&param_idents).map(|(p, id)| {
            let v = lit(p.default);
            quote!(#id: #v)
        });
        let doc = format!(" The runtime parameters of [`{name_str}`], in declaration order.");
        let struct_generics = if generic { quote!(<T>) } else { quote!() };
        quote! {
            #[doc = #doc]
            #[derive(Clone, Copy, Debug, PartialEq)]
            #vis struct #params_name #struct_generics { #(#fields)* }
            impl #impl_generics #params_ty {
                /// The values the description gives.
                pub fn defaults() -> Self { Self { #(#defaults),* } }
            }
        }
    };
    // `-> ()` would trip clippy's `unused_unit` in the user's crate.
    let default_fn = if param_idents.is_empty() {
        quote!(
            fn default_params() {}
        )
    } else {
        quote!(fn default_params() -> #params_ty { #params_name::defaults() })
    };
    let the_struct = if with_struct {
        quote! {
            #(#user_doc)*
            #[doc = ""]
            #[doc = #summary]
            #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
            #vis struct #name;
        }
    } else {
        quote!()
    };
    let coordinates = model
        .joints
        .iter()
        .filter_map(|j| coordinates_tokens(j.kind));
    let tokens = quote! {
        #the_struct

        impl #name {
            /// Number of position coordinates.
            pub const NQ: usize = #nq;
            /// Number of velocity coordinates.
            pub const NV: usize = #nv;
            #(#consts)*
        }

        #params_item

        impl #impl_generics ::articulated::Chain<#scalar> for #name {
            const NAME: &'static str = #name_str;
            const COORDINATES: &'static [::articulated::Coordinates] = &[#(#coordinates),*];
            type Params = #params_ty;
            #default_fn
        }

        #(#items)*
    };
    Ok(Generated { tokens, functions })
}

/// The generated code formatted as a file, with a header saying where it came from.
///
/// # Errors
/// As [`generate`], or if the tokens do not parse as a file (a bug).
pub fn generate_file(model: &Model, options: &Options, source: &str) -> syn::Result<String> {
    let g = generate(model, options)?;
    let body = emit::format(g.tokens)?;
    let mut header = format!(
        "// Generated by articulated-codegen from {source}. Do not edit: regenerate with\n\
         // `articulated expand {source}`.\n//\n"
    );
    for f in &g.functions {
        header.push_str(&format!("// {:<17} {}\n", f.output.name(), f.ops));
    }
    Ok(format!("{header}\n{body}"))
}
