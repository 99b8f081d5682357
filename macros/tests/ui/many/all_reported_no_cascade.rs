// Every error of one `chain!` is reported, in source order, and the code below that uses the
// type (its constants and every trait function) adds none of its own.
use articulated::nalgebra::SVector;
use articulated::prelude::*;

articulated::chain! {
    pub chain Bad {
        scalar: f16;
        body a { mass: 0.0, inertia: diag(1.0, 1.0, 1.0) }
        joint j: revolute(w) { parent: world, child: a }
        joint k: spherical(xyx2) { parent: a, child: nobody }
    }
}

fn main() {
    let q = SVector::<f64, { Bad::NQ }>::zeros();
    let v = SVector::<f64, { Bad::NV }>::zeros();
    let m = Bad::mass_matrix(&q);
    let tau = Bad::inverse_dynamics(&q, &v, &v) + Bad::bias(&q, &v) + Bad::gravity(&q);
    let qdd = Bad::forward_dynamics(&q, &v, &tau).unwrap();
    println!("{} {m} {qdd}", <Bad as Chain<f64>>::NAME);
}
