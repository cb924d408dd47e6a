//! The face terms R_F(u; v) and J_F(u; w, v) of docs/method.md §1.3, §1.7 and §1.8 on the
//! split quadrature of a contact face: the normal part and, with friction, the tangential
//! part.

use super::{dof_dot, FaceDisplacement, FacePoint, Nitsche};
use crate::contact::law::Tangential;
use crate::contact::projection::Smoothing;

impl Nitsche {
    /// Local residual R_F(u; φ_k) and, if asked, Jacobian J_F(u; φ_l, φ_k) (row-major, k × l)
    /// of face k with local nodal displacements `u`. With `frozen`, the Jacobian is that of a
    /// law that does not soften: the cohesion's intact fraction held at its value at `u`
    /// ([`Tangential::d_normal_frozen`]) and a bond's falling slope N' < 0 taken as 0, for the
    /// steps of a stalled Newton run (docs/solver.md §3).
    pub fn face_terms(
        &self,
        k: usize,
        u: &FaceDisplacement,
        smoothing: Smoothing,
        frozen: bool,
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        self.terms(k, u, None, smoothing, frozen, residual, jacobian)
    }

    /// R_F(u_prev; φ_k) + J_F(u_prev; w, φ_k) of face k: its residual of the Newton equation
    /// linearised at `u_prev`, evaluated at u = u_prev + w, with `step` = w
    /// ([`Nitsche::increment`]); its projections from P_γ(u_prev) and the increment alone.
    pub fn linearised_face_terms(
        &self,
        k: usize,
        u_prev: &FaceDisplacement,
        u: &FaceDisplacement,
        step: &FaceDisplacement,
        smoothing: Smoothing,
        residual: &mut [f64],
    ) {
        self.terms(k, u_prev, Some((u, step)), smoothing, false, residual, None)
    }

    /// The face terms at `u`, or with `moved` = (u_new, w), those linearised at `u` evaluated
    /// at u_new = u + w, on the rule of `u` (the linearised integrands are polynomial between
    /// its kinks); the Jacobian with the cohesion's indicator held fixed if `frozen`.
    #[allow(clippy::too_many_arguments)]
    fn terms(
        &self,
        k: usize,
        u: &FaceDisplacement,
        moved: Option<(&FaceDisplacement, &FaceDisplacement)>,
        smoothing: Smoothing,
        frozen: bool,
        residual: &mut [f64],
        mut jacobian: Option<&mut [f64]>,
    ) {
        let n = self.n_local();
        let (gamma, theta, law) = (self.faces[k].gamma, self.theta(k), self.normal_law(k));
        residual[..n].fill(0.0);
        if let Some(j) = jacobian.as_deref_mut() {
            j[..n * n].fill(0.0);
        }
        let mut test = vec![0.0; n];
        let mut trial = vec![0.0; n];
        let zero = FaceDisplacement { relative: vec![0.0; u.relative.len()], normal: 0.0, tangential: 0.0 };
        let (u_new, step) = moved.unwrap_or((u, &zero));
        for (s, w) in self.quadrature(k, u, smoothing) {
            let pt = self.point(k, s);
            let p = self.p_gamma(k, &pt, u);
            let p_u = self.uplift_at(k, pt.x);
            let sigma_n_u = dof_dot(&pt.sigma_n, &u_new.relative) + p_u; // σ'^n(u) = σ^n(u) + p_u
            let [value, tangential] = self.linearised(k, &pt, u, step, smoothing);
            for i in 0..n {
                test[i] = theta * pt.sigma_n[i] - gamma * pt.u_n[i]; // θ σ^n(v) − γ v^n
                trial[i] = pt.sigma_n[i] - gamma * pt.u_n[i]; // σ^n(w) − γ w^n
                residual[i] += (-theta / gamma * sigma_n_u * pt.sigma_n[i] // −(θ/γ) σ'^n(u) σ^n(v)
                    + value * test[i] / gamma // (1/γ) N(P_γ(u))(θσ^n(v) − γv^n)
                    + p_u * pt.u_n[i]) // p_u v^n
                    * w;
            }
            if let Some(j) = jacobian.as_deref_mut() {
                // frozen: the slope of a law that does not soften, N' where it is ≥ 0, else 0
                let slope = law.derivative(p, smoothing);
                let slope = if frozen { slope.max(0.0) } else { slope };
                for r in 0..n {
                    for c in 0..n {
                        j[r * n + c] += (-theta / gamma * pt.sigma_n[c] * pt.sigma_n[r] // −(θ/γ) σ^n(w) σ^n(v)
                            + slope * trial[c] * test[r] / gamma) // (1/γ) N'(P)(σ^n(w) − γw^n)(θσ^n(v) − γv^n)
                            * w;
                    }
                }
            }
            if self.law(k).has_friction() {
                let sigma_t_u = dof_dot(&pt.sigma_t, &u_new.relative);
                let t = self.tangential(k, &pt, u, smoothing);
                let t = if frozen { Tangential { d_normal: t.d_normal_frozen, ..t } } else { t };
                let traction = [sigma_t_u, tangential];
                self.tangential_terms(k, &pt, &t, traction, w, &trial, residual, jacobian.as_deref_mut());
            }
        }
    }

    /// The tangential terms of R_F at one point of face k (weight `w`, `normal_trial` the
    /// σ^n(w) − γ w^n of the basis, `t` the projection there, `traction` = (σ^t(u), Π_S(P^t_γ(u)))
    /// or its linearisation):
    ///
    ///   −(θ/γ) σ^t(u) σ^t(v) + (1/γ) Π_S(P^t_γ(u)) (θ σ^t(v) − γ v^t),
    ///
    /// and their derivative (1/γ)(∂_t Π (σ^t(w) − γ w^t) + ∂_n Π (σ^n(w) − γ w^n))(θσ^t(v) − γv^t)
    /// − (θ/γ) σ^t(w) σ^t(v): Coulomb's threshold couples the normal columns into the
    /// tangential rows, so the Jacobian is not symmetric.
    #[allow(clippy::too_many_arguments)]
    fn tangential_terms(
        &self,
        k: usize,
        pt: &FacePoint,
        t: &Tangential,
        [sigma_t_u, value]: [f64; 2],
        w: f64,
        normal_trial: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        let n = self.n_local();
        let (gamma, theta) = (self.faces[k].gamma, self.theta(k));
        let test: Vec<f64> = (0..n).map(|i| theta * pt.sigma_t[i] - gamma * pt.u_t[i]).collect(); // θ σ^t(v) − γ v^t
        for i in 0..n {
            residual[i] += (-theta / gamma * sigma_t_u * pt.sigma_t[i] // −(θ/γ) σ^t(u) σ^t(v)
                + value * test[i] / gamma) // (1/γ) Π_S(P^t)(θσ^t(v) − γv^t)
                * w;
        }
        if let Some(j) = jacobian {
            for c in 0..n {
                let trial = t.d_tangential * (pt.sigma_t[c] - gamma * pt.u_t[c]) + t.d_normal * normal_trial[c];
                for r in 0..n {
                    j[r * n + c] += (-theta / gamma * pt.sigma_t[c] * pt.sigma_t[r] // −(θ/γ) σ^t(w) σ^t(v)
                        + trial * test[r] / gamma) // (1/γ) dΠ(w) (θσ^t(v) − γv^t)
                        * w;
                }
            }
        }
    }
}
