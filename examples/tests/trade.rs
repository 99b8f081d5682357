//! The trade study's parts that can be checked: the double-double ground truth against the
//! runtime's own Runge–Kutta on generated code (two independent integrations: they must agree
//! to RK4's error, and that error must fall as the fourth power of the step), and the Pareto
//! front's marking.

use articulated::integrate::Method;
use articulated_examples::trade::{
    integrate_once, mark_pareto, truth, Point, TwoLinkF64, TWO_LINK,
};

fn error(q: &[f64], truth: &[f64]) -> f64 {
    q.iter()
        .zip(truth)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
}

#[test]
fn ground_truth_and_generated_rk4_agree_at_fourth_order() {
    let (q_truth, own) = truth(&TWO_LINK);
    assert!(own < 1e-9, "the ground truth's own error {own:e}");
    let e = |dt| {
        let q = integrate_once::<f64, TwoLinkF64, 6, 6>(&TWO_LINK, Method::Rk4, dt).expect("runs");
        error(&q, &q_truth)
    };
    let (coarse, fine) = (e(4e-3), e(1e-3));
    assert!(fine < 1e-7, "{fine:e}");
    let ratio = coarse / fine;
    assert!(
        (100.0..500.0).contains(&ratio),
        "4× the step, {ratio}× the error (4⁴ = 256)"
    );
}

fn point(seconds: f64, error: Option<f64>) -> Point {
    Point {
        scalar: "f64",
        accuracy: "fastest",
        model: "full",
        method: Method::Rk4,
        dt: 1e-3,
        seconds,
        error,
        pareto: false,
    }
}

#[test]
fn the_front_keeps_what_nothing_beats() {
    let mut pts = vec![
        point(1.0, Some(1e-3)),
        point(2.0, Some(1e-2)),    // slower and worse: off
        point(3.0, Some(1e-6)),    // on
        point(0.5, Some(1.0)),     // fastest: on
        point(4.0, Some(0.99e-6)), // better by 1 %: rounding, off
        point(0.1, None),          // stopped: off
    ];
    mark_pareto(&mut pts);
    let on: Vec<bool> = pts.iter().map(|p| p.pareto).collect();
    assert_eq!(on, [true, false, true, true, false, false]);
}
