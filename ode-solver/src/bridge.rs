//! The link between diffsol's `Fn` closures, which live as long as the solver, and the
//! caller's `&mut dyn OdeSystem`, which is only lent for one `step`/`reset` call.

use std::cell::RefCell;
use std::marker::PhantomData;
use std::rc::Rc;

use crate::{OdeSystem, SolverError};

pub(crate) type Shared = Rc<RefCell<Bridge>>;

#[derive(Default)]
pub(crate) struct Bridge {
    /// Set only while an `Attached` guard lives; see `attach` for why this is sound.
    system: Option<*mut (dyn OdeSystem + 'static)>,
    /// First failure inside a closure. diffsol's closures cannot return errors, so the
    /// closure records it and answers NaN, which makes diffsol give up on the step; the
    /// integrator then reports this error instead of diffsol's.
    error: Option<SolverError>,
    /// The state diffsol's `init` closure hands out when a solver is (re)built.
    pub x0: Vec<f64>,
    pub rhs_evaluations: u64,
    pub jacobian_evaluations: u64,
    pub indicator_evaluations: u64,
    fd: FdCache,
}

/// f(t, x) at the point of the last Jacobian: diffsol asks for J·e_j column by column at
/// one point, so caching the base gives n + 1 derivative calls per Jacobian, not 2n.
#[derive(Default)]
struct FdCache {
    valid: bool,
    t: f64,
    x: Vec<f64>,
    f: Vec<f64>,
    x_pert: Vec<f64>,
    f_pert: Vec<f64>,
}

/// Keeps the system lent to the bridge; detaches it when dropped, also on early returns.
pub(crate) struct Attached<'s> {
    shared: Shared,
    _lent: PhantomData<&'s mut ()>,
}

impl Drop for Attached<'_> {
    fn drop(&mut self) {
        self.shared.borrow_mut().system = None;
    }
}

/// Lend `system` to the closures for the guard's lifetime.
///
/// Soundness: the guard holds the exclusive borrow `'s`, so nothing else can touch the
/// system meanwhile; the pointer is cleared in `Drop` before the borrow ends, and it is
/// only dereferenced in `Bridge` methods, one at a time under the `RefCell`.
pub(crate) fn attach<'s>(shared: &Shared, system: &'s mut (dyn OdeSystem + 's)) -> Attached<'s> {
    let ptr: *mut (dyn OdeSystem + 's) = system;
    // SAFETY: only erases the trait object's lifetime bound; see the soundness note above.
    let ptr: *mut (dyn OdeSystem + 'static) = unsafe { std::mem::transmute(ptr) };
    let mut b = shared.borrow_mut();
    b.system = Some(ptr);
    // The system may have changed (parameters, mode) since the last call.
    b.fd.valid = false;
    drop(b);
    Attached {
        shared: shared.clone(),
        _lent: PhantomData,
    }
}

impl Bridge {
    pub fn take_error(&mut self) -> Option<SolverError> {
        self.error.take()
    }

    fn system(&mut self) -> Result<&mut dyn OdeSystem, SolverError> {
        match self.system {
            // SAFETY: set only while an `Attached` guard holds the exclusive borrow.
            Some(p) => Ok(unsafe { &mut *p }),
            None => Err(SolverError::Backend("no system attached".into())),
        }
    }

    /// For diffsol's rhs closure: never fails, records the error and returns NaN instead.
    pub fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) {
        if self.error.is_none() {
            self.error = self.derivatives(t, x, dx).err();
        }
        if self.error.is_some() {
            dx.fill(f64::NAN);
        }
    }

    fn derivatives(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), SolverError> {
        self.rhs_evaluations += 1;
        self.system()?
            .derivatives(t, x, dx)
            .map_err(|message| SolverError::System { t, message })?;
        match dx.iter().position(|v| !v.is_finite()) {
            Some(index) => Err(SolverError::NonFiniteDerivative { t, index }),
            None => Ok(()),
        }
    }

    /// For diffsol's Jacobian-vector closure: forward difference along `v`.
    pub fn jac_mul(&mut self, t: f64, x: &[f64], v: &[f64], jv: &mut [f64]) {
        let vmax = v.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        if vmax == 0.0 {
            jv.fill(0.0);
            return;
        }
        let mut fd = std::mem::take(&mut self.fd);
        if !(fd.valid && fd.t == t && fd.x == x) {
            fd.x.clear();
            fd.x.extend_from_slice(x);
            fd.f.resize(x.len(), 0.0);
            fd.t = t;
            self.rhs(t, x, &mut fd.f);
            fd.valid = self.error.is_none();
            self.jacobian_evaluations += 1;
        }
        // sqrt(eps) balances truncation and cancellation; scaled by the magnitude of the
        // perturbed components so large states (h = 800 m) are not under-perturbed.
        let xmax = x
            .iter()
            .zip(v)
            .filter(|(_, vi)| **vi != 0.0)
            .fold(0.0f64, |m, (xi, _)| m.max(xi.abs()));
        let sigma = f64::EPSILON.sqrt() * (1.0 + xmax) / vmax;
        fd.x_pert.clear();
        fd.x_pert
            .extend(x.iter().zip(v).map(|(xi, vi)| xi + sigma * vi));
        fd.f_pert.resize(x.len(), 0.0);
        self.rhs(t, &fd.x_pert, &mut fd.f_pert);
        for ((out, fp), f0) in jv.iter_mut().zip(&fd.f_pert).zip(&fd.f) {
            *out = (fp - f0) / sigma;
        }
        self.fd = fd;
    }

    pub fn indicators(&mut self, t: f64, x: &[f64], z: &mut [f64]) -> Result<(), SolverError> {
        if z.is_empty() {
            return Ok(());
        }
        self.indicator_evaluations += 1;
        self.system()?
            .indicators(t, x, z)
            .map_err(|message| SolverError::System { t, message })?;
        match z.iter().position(|v| !v.is_finite()) {
            Some(index) => Err(SolverError::NonFiniteIndicator { t, index }),
            None => Ok(()),
        }
    }
}
