//! The chain description language: one grammar for the `chain!{}` macro and `.chain` files.
//!
//! This module turns tokens into a [`ChainDef`], a syntax tree that keeps the span of every
//! name and number so that [`crate::lower`] can point each error at the user's token. Nothing is
//! checked here beyond the shape of the syntax; [`crate::lower::lower`] checks the meaning (names,
//! the tree, masses, inertias) and reports every error at once.
//!
//! # By example: Hemami's two-link system
//!
//! ```text
//! /// Hemami's two-link system: legs on a spherical ankle, trunk on a spherical hip.
//! pub chain TwoLink {
//!     gravity: [0.0, 0.0, -9.81];
//!     scalar: f64;
//!     outputs: [mass_matrix, bias, gravity, inverse_dynamics, forward_dynamics];
//!     param trunk_mass = 40.0;
//!
//!     body legs {
//!         mass: 30.0,
//!         com: [0.0, 0.0, 0.45],
//!         inertia: diag(2.6, 2.5, 0.25),
//!     }
//!     body trunk { mass: trunk_mass, com: [0.0, 0.0, 0.35], inertia: diag(1.6, 1.2, 0.45) }
//!
//!     joint ankle: spherical(xyz) { parent: world, child: legs }
//!     joint hip: spherical(xyz) { parent: legs, child: trunk, xyz: [0.0, 0.0, 0.9], rpy: [0.0, 0.0, 0.0] }
//! }
//! ```
//!
//! The same text is a `.chain` file (read it with [`crate::load::load`]) and, inside
//! `chain! { … }`, a macro invocation. Comments are Rust's: `//`, `/* … */`, and `///` doc
//! comments.
//!
//! # The header
//! `[doc comments] [visibility] chain Name { items }`
//!
//! - Doc comments (`/// …`, or `#[doc = "…"]`) before `chain` become the generated type's docs
//!   ([`Options::doc`](crate::options::Options::doc), one entry per line, exactly as written).
//! - Visibility: none, `pub`, `pub(crate)`, `pub(super)`, `pub(in path)`: copied to
//!   [`Options::visibility`](crate::options::Options::visibility).
//! - `chain` is a contextual keyword; `Name` names the generated type.
//! - An optional `;` may follow the closing brace.
//!
//! # Items
//! Items come in any order. Each may be preceded by doc comments, which are accepted and
//! ignored (use them to document your bodies and joints).
//!
//! ## Settings: `key: value;`
//! | setting | values | when absent |
//! |---|---|---|
//! | `gravity` | `[gx, gy, gz]` (m/s², world frame) or `none` | `[0.0, 0.0, -9.81]` |
//! | `scalar` | `f64`, `f32` or `generic` | `f64` |
//! | `frames` | a list of frame names (bodies' or `frame` items'), for the frame outputs | none |
//! | `contacts` | a list of `frame: kind`, `kind` being `six_d` (the whole frame held: 6 rows, a wrench `[n; f]` in its axes) or `point` (its origin held: 3 rows, a force in world axes): `[left_sole: six_d, toe: point]` | none |
//! | `loops` | a list of `name: point(a, b)`, frame `a`'s origin held on frame `b`'s (3 rows, a force in world axes): `[rod: point(tip, ground)]` | none |
//! | `outputs` | a list of names from [`Output::ALL`](crate::options::Output::ALL) (`mass_matrix`, `bias`, `gravity`, `inverse_dynamics`, `forward_dynamics`, …) or of groups ([`Group`](crate::outputs::Group): `dynamics`, `kept`, `wrenches`, `whole_body`, `derivatives`) | [`Output::DEFAULT`](crate::options::Output::DEFAULT) |
//!
//! Outputs are sorted and duplicates dropped.
//!
//! `contacts` and `loops` declare the constraints the generated
//! `constrained_forward_dynamics(q, v, tau)` holds, generated for that set in the chain's
//! scalar: a contact per frame, a loop per name, on
//! frames that move, and no more rows (3 per point and loop, 6 per `six_d`) than velocities.
//! Their frames join `frames` (appended in order where absent) and the outputs the runtime's
//! solver reads are generated too, for any subset of them at run time
//! ([`Options::resolved`](crate::options::Options::resolved)). The type gains `CONTACTS`, `LOOPS`
//! (frames by their index in `FRAMES`), `CONSTRAINT_ROWS` and
//! `CONSTRAINED_FORWARD_DYNAMICS_OPS`.
//!
//! ## Parameters: `param name = default;`
//! A runtime parameter: a number the generated code takes as an argument instead of baking it
//! in (a payload, a mass being identified). The default must be a constant. A parameter name
//! may stand wherever a number does (`mass: trunk_mass`), except in a joint axis, but only
//! alone: `2.0 * trunk_mass` is an error. Checks (positive mass, inertia) use the default.
//!
//! ## Bodies: `body name { field: value, … }`
//! | field | value | required |
//! |---|---|---|
//! | `mass` | kg | yes |
//! | `com` | `[x, y, z]`: centre of mass in the body frame (m) | no, `[0.0, 0.0, 0.0]` |
//! | `inertia` | about the centre of mass, body axes (kg·m²): principal moments `diag(ixx, iyy, izz)`, or a full symmetric matrix `[[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]` | yes |
//!
//! A trailing comma and a `;` after the block are allowed. A body that moves (one not attached
//! to the world through `fixed` joints only) needs a positive mass and a positive definite
//! inertia; every inertia must be symmetric and satisfy the triangle inequality (each principal
//! moment at most the sum of the other two).
//!
//! ## Joints: `joint name: kind { field: value, … }`
//! | kind | motion | `q` | `v` |
//! |---|---|---|---|
//! | `revolute(x)`, `revolute(y)`, `revolute(z)` (or `-x`, `-y`, `-z`), `revolute([ax, ay, az])` | rotation about the axis (normalized) | 1 | 1 |
//! | `prismatic(x)`, …, `prismatic([ax, ay, az])` | translation along the axis | 1 | 1 |
//! | `spherical(xyz)`, or any of the 12 Euler sequences | three Euler angles, intrinsic (`xyz`: `R = Rx·Ry·Rz`) | 3 | 3 |
//! | `spherical(quaternion)` | quaternion `[w, x, y, z]` | 4 | 3 |
//! | `free` (= `free(zyx)`, Wieber's form), `free(SEQ)` | translation, then Euler angles | 6 | 6 |
//! | `free(quaternion)` | translation, then a quaternion | 7 | 6 |
//! | `fixed` | none | 0 | 0 |
//!
//! The 12 Euler sequences are `xyz`, `xzy`, `yxz`, `yzx`, `zxy`, `zyx` (Tait–Bryan) and `xyx`,
//! `xzx`, `yxy`, `yzy`, `zxz`, `zyz` (proper Euler). Axis components must be constants.
//!
//! | field | value | required |
//! |---|---|---|
//! | `parent` | `world` or a body | yes |
//! | `child` | a body | yes |
//! | `xyz` | `[x, y, z]`: the joint frame's origin in the parent frame (m) | no, zero |
//! | `rpy` | `[roll, pitch, yaw]` (rad): the joint frame's rotation, `R = Rz(yaw)·Ry(pitch)·Rx(roll)` | no, zero |
//! | `armature` | rotor inertia on each of the joint's velocities (kg·m² or kg), `≥ 0`: added to `M`'s diagonal | no, zero |
//! | `damping` | viscous damping (N·m·s/rad or N·s/m), `≥ 0` | no, zero |
//! | `friction` | dry friction (N·m or N), `≥ 0` | no, zero |
//! | `lower`, `upper` | position limits (rad or m), `lower ≤ upper`; revolute and prismatic joints only | no, none |
//! | `velocity` | speed limit (rad/s or m/s), `> 0` | no, none |
//! | `effort` | the actuator's largest force (N·m or N), `> 0` | no, none |
//! | `mimic` | the joint this one follows (URDF's `<mimic>`) | no |
//! | `multiplier`, `offset` | with `mimic`: the coordinate is `multiplier·q_followed + offset` | no, 1 and 0 |
//!
//! The drive fields (`armature` to `effort`, constants only) become the joint's
//! [`Drive`](crate::model::Drive): the armature is part of the generated dynamics; damping,
//! friction and limits are forces the runtime's `articulated::drives` applies in a simulation.
//!
//! A joint with `mimic: other` is a [`Mimic`](crate::model::Mimic) joint: it has no coordinate
//! of its own (it leaves `q` and `v`, as in Pinocchio 3) and turns or slides by
//! `multiplier·q_other + offset`; the dynamics are the coupled ones, `M = Gᵀ·M_tree·G`. Both
//! joints are revolute or prismatic, `other` mimics nothing itself, and the mimic joint may have
//! an `armature` (reflected onto `other` by `multiplier²`) but no damping, friction or limits.
//!
//! Every body is the child of exactly one joint, and every body must be reachable from
//! `world`. In the [`Model`](crate::model::Model), bodies and joints are stored depth-first from
//! the world, children in joint declaration order, whatever order the items come in.
//!
//! ## Frames: `frame name { parent: body, xyz: […], rpy: […] }`
//! A frame fixed to a body (or to `world`): a tool tip, a foot sole, a sensor. `xyz` and `rpy`
//! place it in its parent's frame as a joint is placed (zero when absent). Every body is a frame
//! too, under its own name. Names are unique among bodies and frames. Which frames the generated
//! code computes is the setting `frames: [tool, left_sole];` (in that order), with the frame
//! outputs (`frame_placements`, …, or the group `frames`).
//!
//! ## Numbers
//! A number is a constant expression, folded when the description is read: integer and float
//! literals, `pi`, unary `-`, binary `+ - * /` (usual precedence) and parentheses, e.g.
//! `rpy: [0.0, pi / 2.0, 0.0]` or `mass: 2 * (1.5 + 0.25)`. Or a parameter name standing alone.
//! Results must be finite: `1e999` and `1.0 / 0.0` are errors.
//!
//! # Errors
//! A syntax error stops parsing at the first bad token. Everything else is checked by
//! [`crate::lower::lower`], which reports all errors at once, each at the offending token.
//!
//! # Example
//! ```
//! use articulated_codegen::load::parse_chain_str;
//! let src = r#"
//!     /// A pendulum.
//!     pub chain Pendulum {
//!         param m = 1.0;
//!         body bob { mass: m, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
//!         joint pivot: revolute(y) { parent: world, child: bob }
//!     }
//! "#;
//! let chain = parse_chain_str(src, "pendulum.chain".as_ref()).unwrap();
//! assert_eq!(chain.model.name, "Pendulum");
//! assert_eq!((chain.model.nq(), chain.model.nv()), (1, 1));
//! assert_eq!(chain.options.doc, [" A pendulum."]);
//! ```

mod expr;

pub use expr::{BinOp, Expr};

use std::fmt;

use proc_macro2::{Ident, TokenStream};
use quote::{ToTokens, TokenStreamExt};
use syn::ext::IdentExt;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{braced, parenthesized, token, Attribute, Token, Visibility};

/// A whole chain description: `[docs] [vis] chain Name { items }`. Parse it with
/// `syn::parse2::<ChainDef>(tokens)` (or `syn::parse_macro_input!`); lower it with
/// [`crate::lower::lower`].
#[derive(Clone, Debug)]
pub struct ChainDef {
    /// Attributes before `chain`: doc comments (anything else is reported by `lower`).
    pub attrs: Vec<Attribute>,
    /// The visibility of the generated type.
    pub vis: Visibility,
    /// The contextual keyword `chain`.
    pub chain_token: Ident,
    /// The chain's name.
    pub name: Ident,
    /// The braces around the items.
    pub brace: token::Brace,
    /// The items, in source order.
    pub items: Vec<Item>,
    /// An optional `;` after the closing brace.
    pub semi: Option<Token![;]>,
}

/// One item of a chain.
#[derive(Clone, Debug)]
pub enum Item {
    /// `key: value;`
    Setting(Setting),
    /// `param name = default;`
    Param(ParamDef),
    /// `body name { … }`
    Body(BodyDef),
    /// `joint name: kind { … }`
    Joint(JointDef),
    /// `frame name { parent: …, xyz: […], rpy: […] }`
    Frame(FrameDef),
}

/// A frame fixed to a body or the world: `frame name { parent: body, xyz: […], rpy: […] }`.
#[derive(Clone, Debug)]
pub struct FrameDef {
    /// Doc comments before it (ignored).
    pub attrs: Vec<Attribute>,
    /// The contextual keyword `frame`.
    pub frame_token: Ident,
    /// The frame's name.
    pub name: Ident,
    /// The braces.
    pub brace: token::Brace,
    /// The fields, in source order.
    pub fields: Punctuated<Field, Token![,]>,
    /// An optional `;` after the block.
    pub semi: Option<Token![;]>,
}

/// A setting: `gravity: …;`, `scalar: …;`, `outputs: […];`.
#[derive(Clone, Debug)]
pub struct Setting {
    /// Doc comments before it (ignored).
    pub attrs: Vec<Attribute>,
    /// Which setting.
    pub key: Ident,
    /// The `:`.
    pub colon: Token![:],
    /// Its value.
    pub value: Expr,
    /// The closing `;`.
    pub semi: Token![;],
}

/// A runtime parameter: `param name = default;`.
#[derive(Clone, Debug)]
pub struct ParamDef {
    /// Doc comments before it (ignored).
    pub attrs: Vec<Attribute>,
    /// The contextual keyword `param`.
    pub param_token: Ident,
    /// The parameter's name.
    pub name: Ident,
    /// The `=`.
    pub eq: Token![=],
    /// Its default value.
    pub default: Expr,
    /// The closing `;`.
    pub semi: Token![;],
}

/// A body: `body name { mass: …, com: […], inertia: … }`.
#[derive(Clone, Debug)]
pub struct BodyDef {
    /// Doc comments before it (ignored).
    pub attrs: Vec<Attribute>,
    /// The contextual keyword `body`.
    pub body_token: Ident,
    /// The body's name.
    pub name: Ident,
    /// The braces.
    pub brace: token::Brace,
    /// The fields, in source order.
    pub fields: Punctuated<Field, Token![,]>,
    /// An optional `;` after the block.
    pub semi: Option<Token![;]>,
}

/// A joint: `joint name: kind { parent: …, child: …, xyz: […], rpy: […] }`.
#[derive(Clone, Debug)]
pub struct JointDef {
    /// Doc comments before it (ignored).
    pub attrs: Vec<Attribute>,
    /// The contextual keyword `joint`.
    pub joint_token: Ident,
    /// The joint's name.
    pub name: Ident,
    /// The `:` before the kind.
    pub colon: Token![:],
    /// The joint kind and its arguments.
    pub kind: KindDef,
    /// The braces.
    pub brace: token::Brace,
    /// The fields, in source order.
    pub fields: Punctuated<Field, Token![,]>,
    /// An optional `;` after the block.
    pub semi: Option<Token![;]>,
}

/// A joint kind as written: `fixed`, `free`, `revolute(z)`, `spherical(xyz)`, ….
#[derive(Clone, Debug)]
pub struct KindDef {
    /// `revolute`, `prismatic`, `spherical`, `free` or `fixed` (checked by `lower`).
    pub name: Ident,
    /// The parenthesized arguments, if any.
    pub args: Option<(token::Paren, Punctuated<Expr, Token![,]>)>,
}

/// A field of a body or joint block: `key: value`.
#[derive(Clone, Debug)]
pub struct Field {
    /// The field's name.
    pub key: Ident,
    /// The `:`.
    pub colon: Token![:],
    /// Its value.
    pub value: Expr,
}

fn is_word(input: ParseStream, word: &str) -> bool {
    input.peek(Ident::peek_any) && input.fork().call(Ident::parse_any).is_ok_and(|i| i == word)
}

impl Parse for ChainDef {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let vis: Visibility = input.parse()?;
        let chain_token: Ident = if is_word(input, "chain") {
            input.call(Ident::parse_any)?
        } else {
            return Err(input.error("expected `chain Name { … }`"));
        };
        let name: Ident = input.parse()?;
        let content;
        let brace = braced!(content in input);
        let mut items = Vec::new();
        while !content.is_empty() {
            items.push(content.parse()?);
        }
        let semi = input.parse()?;
        Ok(ChainDef {
            attrs,
            vis,
            chain_token,
            name,
            brace,
            items,
            semi,
        })
    }
}

impl Parse for Item {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let is_setting =
            input.peek(Ident::peek_any) && input.peek2(Token![:]) && !input.peek2(Token![::]);
        if is_setting {
            Ok(Item::Setting(Setting {
                attrs,
                key: input.call(Ident::parse_any)?,
                colon: input.parse()?,
                value: input.parse()?,
                semi: input.parse()?,
            }))
        } else if is_word(input, "param") {
            Ok(Item::Param(ParamDef {
                attrs,
                param_token: input.call(Ident::parse_any)?,
                name: input.parse()?,
                eq: input.parse()?,
                default: input.parse()?,
                semi: input.parse()?,
            }))
        } else if is_word(input, "body") {
            let body_token = input.call(Ident::parse_any)?;
            let name = input.parse()?;
            let content;
            let brace = braced!(content in input);
            let fields = content.parse_terminated(Field::parse, Token![,])?;
            Ok(Item::Body(BodyDef {
                attrs,
                body_token,
                name,
                brace,
                fields,
                semi: input.parse()?,
            }))
        } else if is_word(input, "joint") {
            let joint_token = input.call(Ident::parse_any)?;
            let name = input.parse()?;
            let colon = input.parse()?;
            let kind = input.parse()?;
            let content;
            let brace = braced!(content in input);
            let fields = content.parse_terminated(Field::parse, Token![,])?;
            Ok(Item::Joint(JointDef {
                attrs,
                joint_token,
                name,
                colon,
                kind,
                brace,
                fields,
                semi: input.parse()?,
            }))
        } else if is_word(input, "frame") {
            let frame_token = input.call(Ident::parse_any)?;
            let name = input.parse()?;
            let content;
            let brace = braced!(content in input);
            let fields = content.parse_terminated(Field::parse, Token![,])?;
            Ok(Item::Frame(FrameDef {
                attrs,
                frame_token,
                name,
                brace,
                fields,
                semi: input.parse()?,
            }))
        } else {
            Err(input.error(
                "expected `body name { … }`, `joint name: kind { … }`, `frame name { … }`, \
                 `param name = value;` or a setting `key: value;`",
            ))
        }
    }
}

impl Parse for KindDef {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name = input.call(Ident::parse_any)?;
        let args = if input.peek(token::Paren) {
            let content;
            let paren = parenthesized!(content in input);
            Some((paren, content.parse_terminated(Expr::parse, Token![,])?))
        } else {
            None
        };
        Ok(KindDef { name, args })
    }
}

impl Parse for Field {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        Ok(Field {
            key: input.call(Ident::parse_any)?,
            colon: input.parse()?,
            value: input.parse()?,
        })
    }
}

impl ToTokens for KindDef {
    fn to_tokens(&self, tokens: &mut TokenStream) {
        self.name.to_tokens(tokens);
        if let Some((paren, args)) = &self.args {
            paren.surround(tokens, |t| args.to_tokens(t));
        }
    }
}

impl ToTokens for Field {
    fn to_tokens(&self, tokens: &mut TokenStream) {
        self.key.to_tokens(tokens);
        self.colon.to_tokens(tokens);
        self.value.to_tokens(tokens);
    }
}

impl ToTokens for ChainDef {
    fn to_tokens(&self, tokens: &mut TokenStream) {
        tokens.append_all(&self.attrs);
        self.vis.to_tokens(tokens);
        self.chain_token.to_tokens(tokens);
        self.name.to_tokens(tokens);
        self.brace.surround(tokens, |t| {
            for item in &self.items {
                item.to_tokens(t);
            }
        });
        self.semi.to_tokens(tokens);
    }
}

impl ToTokens for Item {
    fn to_tokens(&self, tokens: &mut TokenStream) {
        match self {
            Item::Setting(s) => {
                tokens.append_all(&s.attrs);
                s.key.to_tokens(tokens);
                s.colon.to_tokens(tokens);
                s.value.to_tokens(tokens);
                s.semi.to_tokens(tokens);
            }
            Item::Param(p) => {
                tokens.append_all(&p.attrs);
                p.param_token.to_tokens(tokens);
                p.name.to_tokens(tokens);
                p.eq.to_tokens(tokens);
                p.default.to_tokens(tokens);
                p.semi.to_tokens(tokens);
            }
            Item::Body(b) => {
                tokens.append_all(&b.attrs);
                b.body_token.to_tokens(tokens);
                b.name.to_tokens(tokens);
                b.brace.surround(tokens, |t| b.fields.to_tokens(t));
                b.semi.to_tokens(tokens);
            }
            Item::Frame(f) => {
                tokens.append_all(&f.attrs);
                f.frame_token.to_tokens(tokens);
                f.name.to_tokens(tokens);
                f.brace.surround(tokens, |t| f.fields.to_tokens(t));
                f.semi.to_tokens(tokens);
            }
            Item::Joint(j) => {
                tokens.append_all(&j.attrs);
                j.joint_token.to_tokens(tokens);
                j.name.to_tokens(tokens);
                j.colon.to_tokens(tokens);
                j.kind.to_tokens(tokens);
                j.brace.surround(tokens, |t| j.fields.to_tokens(t));
                j.semi.to_tokens(tokens);
            }
        }
    }
}

impl fmt::Display for KindDef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.name)?;
        if let Some((_, args)) = &self.args {
            f.write_str("(")?;
            for (i, e) in args.iter().enumerate() {
                if i > 0 {
                    f.write_str(", ")?;
                }
                write!(f, "{e}")?;
            }
            f.write_str(")")?;
        }
        Ok(())
    }
}
