// Every rule of the check stage one `chain!` breaks is reported at once, each at the user's
// token: the output and the accuracy that do not go with the model at their names, a massless
// moving body at its mass, an inertia that is not symmetric at the element below the diagonal,
// a mimic of a mimic joint at the name it follows, a second parent at the `child:` value.
articulated::chain! {
    pub chain Broken {
        accuracy: robust;
        outputs: [joint_wrenches_bottom_up, forward_dynamics];
        body trunk { mass: 0.0, inertia: diag(1.0, 1.0, 1.0) }
        body arm {
            mass: 1.0,
            inertia: [[1.0, 0.1, 0.0], [0.2, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        body finger { mass: 0.1, inertia: diag(0.01, 0.01, 0.01) }
        body thumb { mass: 0.1, inertia: diag(0.01, 0.01, 0.01) }
        joint waist: revolute(z) { parent: world, child: trunk }
        joint shoulder: revolute(y) { parent: trunk, child: arm }
        joint grip: revolute(x) { parent: trunk, child: finger, mimic: shoulder }
        joint pinch: revolute(x) { parent: arm, child: thumb, mimic: grip }
        joint again: revolute(x) { parent: trunk, child: thumb }
    }
}

fn main() {
    let _ = Broken::NV;
}
