//! Bringing your own vehicle: LanderGnc flown through its C functions (FMI 2.0, read then
//! step; FMI 3.0 Step Mode, step then read) against a rigid-body plant written here, apart
//! from the project's physics: 1,000 kg, principal inertia 900/700/1,000 kg m2, thrust
//! 800-2,400 N along its own body +z, +-200 N m, lunar gravity. The plant's body is not the
//! GNC's: a constant rotation at the interface maps the GNC's thrust axis (body +y) onto the
//! plant's +z (docs/interface.md, "Bringing your own vehicle").
//!
//! Wired correctly, the flight raises nothing. Each convention mistake a user made with such
//! a plant (scalar-last or conjugate quaternion, rates in deg/s, ENU position and velocity,
//! gravity 9.81, an inertia 1,000 times the declared one, a weight above thrust_max) is
//! named by one message within 2 s of its appearance, and no warning is logged twice.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use fmi_testkit::{fmi2_functions, fmi3_functions, Fmi2, Fmi2Functions, Fmi3, Fmi3Functions};
use fmu_gnc::LanderGnc;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

static FUNCTIONS2: Fmi2Functions = fmi2_functions!(fmu_gnc);
static FUNCTIONS3: Fmi3Functions = fmi3_functions!(fmu_gnc);

const H: f64 = 0.01;
const MOON_GRAVITY: f64 = 1.62;

/// The plant's body: +z the thrust axis.
#[derive(Debug, Clone, Copy)]
struct Plant {
    r_nue: Vector3<f64>,
    v_nue: Vector3<f64>,
    q_plant_to_nue: UnitQuaternion<f64>,
    omega_plant: Vector3<f64>,
    mass_kg: f64,
    inertia_plant: Vector3<f64>,
}

/// Plant body from GNC body: +90 deg about x takes the GNC's +y (thrust) to the plant's +z.
fn gnc_to_plant() -> UnitQuaternion<f64> {
    let half = std::f64::consts::FRAC_PI_4;
    UnitQuaternion::new_unchecked(Quaternion::new(half.cos(), half.sin(), 0.0, 0.0))
}

impl Plant {
    fn new(inertia_scale: f64) -> Plant {
        // 15 deg tilted toward North, as the paper's scenario starts, with a small rate
        let tilt = 15f64.to_radians();
        let q_gnc_to_nue = UnitQuaternion::new_unchecked(Quaternion::new(
            (tilt / 2.0).cos(),
            0.0,
            0.0,
            -(tilt / 2.0).sin(),
        ));
        Plant {
            r_nue: Vector3::new(0.0, 800.0, 0.0),
            v_nue: Vector3::zeros(),
            q_plant_to_nue: q_gnc_to_nue * gnc_to_plant().inverse(),
            omega_plant: Vector3::new(0.01, -0.02, 0.01),
            mass_kg: 1000.0,
            inertia_plant: Vector3::new(900.0, 700.0, 1000.0) * inertia_scale,
        }
    }

    /// Thrust `thrust_n` along plant +z and `torque_plant` over `dt`, in 10 sub-steps.
    fn step(&mut self, thrust_n: f64, torque_plant: Vector3<f64>, dt: f64) {
        let thrust_n = if thrust_n <= 1.0 {
            0.0
        } else {
            thrust_n.clamp(800.0, 2400.0)
        };
        let torque = torque_plant.map(|t| t.clamp(-200.0, 200.0));
        let n = 10;
        let dt = dt / f64::from(n);
        for _ in 0..n {
            let a = self.q_plant_to_nue * Vector3::z() * (thrust_n / self.mass_kg)
                + Vector3::new(0.0, -MOON_GRAVITY, 0.0);
            self.r_nue += self.v_nue * dt + a * (0.5 * dt * dt);
            self.v_nue += a * dt;
            let i = self.inertia_plant;
            let w = self.omega_plant;
            let w_dot = (torque - w.cross(&i.component_mul(&w))).component_div(&i);
            let w_mid = w + w_dot * (0.5 * dt);
            self.omega_plant = w + w_dot * dt;
            let q = self.q_plant_to_nue.into_inner();
            let dq = q * Quaternion::from_imag(w_mid) * 0.5;
            self.q_plant_to_nue = UnitQuaternion::from_quaternion(q + dq * dt);
        }
    }

    /// What the GNC is given (its conventions, through the constant rotation).
    fn navigation(&self) -> ([f64; 3], [f64; 3], [f64; 4], [f64; 3]) {
        let q = self.q_plant_to_nue * gnc_to_plant();
        let omega_gnc = gnc_to_plant().inverse() * self.omega_plant;
        (
            self.r_nue.into(),
            self.v_nue.into(),
            [q.w, q.i, q.j, q.k],
            omega_gnc.into(),
        )
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Mistake {
    None,
    ScalarLast,
    Conjugate,
    DegreesPerSecond,
    Enu,
    EarthGravity,
    InertiaThousandfold,
    WeightAboveThrustMax,
}

/// What the GNC is given under `mistake`, at 14 values in the order of its inputs.
fn wired(plant: &Plant, mistake: Mistake) -> [f64; 14] {
    let (mut r, mut v, mut q, mut w) = plant.navigation();
    match mistake {
        Mistake::ScalarLast => q = [q[1], q[2], q[3], q[0]],
        Mistake::Conjugate => q = [q[0], -q[1], -q[2], -q[3]],
        Mistake::DegreesPerSecond => w = w.map(f64::to_degrees),
        Mistake::Enu => {
            r = [r[2], r[0], r[1]];
            v = [v[2], v[0], v[1]];
        }
        _ => {}
    }
    let mut x = [0.0; 14];
    x[..3].copy_from_slice(&r);
    x[3..6].copy_from_slice(&v);
    x[6..10].copy_from_slice(&q);
    x[10..13].copy_from_slice(&w);
    x[13] = plant.mass_kg;
    x
}

/// The GNC's parameters for this plant (in its own body axes), but for the parameter
/// mistakes.
fn parameters(mistake: Mistake) -> Vec<(u32, Vec<f64>)> {
    let inertia_gnc = [900.0, 1000.0, 700.0];
    let mut p = vec![
        (201, vec![150f64.to_radians()]),
        (208, inertia_gnc.to_vec()),
        (211, vec![800.0]),
        (212, vec![2400.0]),
        (213, vec![200.0; 3]),
        (216, vec![MOON_GRAVITY]),
    ];
    match mistake {
        Mistake::EarthGravity => p.push((216, vec![9.81])),
        // the GNC's default
        Mistake::WeightAboveThrustMax => p.push((212, vec![1600.0])),
        _ => {}
    }
    p
}

/// One LanderGnc instance in either version, as this test drives it.
trait Gnc {
    fn start(mistake: Mistake) -> Self;
    fn set_inputs(&self, x: &[f64; 14]);
    /// thrust_cmd, torque_cmd_body
    fn commands(&self) -> [f64; 4];
    fn step(&self, t: f64, h: f64);
    fn messages(&self) -> Vec<String>;
    /// Read before the step (FMI 2.0) or after it (FMI 3.0 Step Mode, one step late).
    const READ_BEFORE_STEP: bool;
}

impl Gnc for Fmi2 {
    const READ_BEFORE_STEP: bool = true;
    fn start(mistake: Mistake) -> Fmi2 {
        let gnc = Fmi2::instantiate(&FUNCTIONS2, "gnc", &fmi2_export::guid::<LanderGnc>());
        gnc.enter_init();
        for (vr, values) in parameters(mistake) {
            let vrs: Vec<u32> = (vr..vr + values.len() as u32).collect();
            assert!(gnc.set_reals(&vrs, &values).is_success());
        }
        assert!(
            gnc.exit_initialization_mode().is_success(),
            "{:?}",
            gnc.messages()
        );
        gnc
    }
    fn set_inputs(&self, x: &[f64; 14]) {
        let vrs: Vec<u32> = (1..=14).collect();
        assert!(self.set_reals(&vrs, x).is_success());
    }
    fn commands(&self) -> [f64; 4] {
        let (status, out) = self.get_reals(&[100, 101, 102, 103]);
        assert!(status.is_success());
        [out[0], out[1], out[2], out[3]]
    }
    fn step(&self, t: f64, h: f64) {
        assert!(
            self.do_step(t, h).is_success(),
            "{:?}",
            Fmi2::messages(self)
        );
    }
    fn messages(&self) -> Vec<String> {
        Fmi2::messages(self)
    }
}

impl Gnc for Fmi3 {
    const READ_BEFORE_STEP: bool = false;
    fn start(mistake: Mistake) -> Fmi3 {
        let token = fmi3_export::instantiation_token::<LanderGnc>();
        let gnc = Fmi3::co_simulation(&FUNCTIONS3, "gnc", &token, Default::default())
            .expect("instantiated");
        assert_eq!(gnc.enter_initialization_mode(0.0, None).0, 0);
        for (vr, values) in parameters(mistake) {
            assert_eq!(gnc.set_float64(&[vr], &values).0, 0, "{vr}");
        }
        assert!(
            gnc.exit_initialization_mode().0 <= 1,
            "{:?}",
            gnc.messages()
        );
        gnc
    }
    fn set_inputs(&self, x: &[f64; 14]) {
        assert!(self.set_float64(&[1, 4, 7, 11, 14], x).0 <= 1);
    }
    fn commands(&self) -> [f64; 4] {
        let (status, out) = self.get_float64(&[100, 101], 4);
        assert!(status.0 <= 1);
        [out[0], out[1], out[2], out[3]]
    }
    fn step(&self, t: f64, h: f64) {
        let s = self.do_step(t, h);
        assert!(s.status.0 <= 1, "{:?}", Fmi3::messages(self));
    }
    fn messages(&self) -> Vec<String> {
        Fmi3::messages(self)
    }
}

/// What one flight logged, and whether the plant stayed aloft.
struct Flight {
    messages: Vec<String>,
    lowest_height_m: f64,
}

fn fly<G: Gnc>(mistake: Mistake, duration_s: f64) -> Flight {
    let gnc = G::start(mistake);
    let inertia_scale = if mistake == Mistake::InertiaThousandfold {
        1000.0
    } else {
        1.0
    };
    let mut plant = Plant::new(inertia_scale);
    let mut lowest_height_m = plant.r_nue.y;
    let mut command = gnc.commands();
    let steps = (duration_s / H).round() as usize;
    for k in 0..steps {
        let t = k as f64 * H;
        gnc.set_inputs(&wired(&plant, mistake));
        if G::READ_BEFORE_STEP {
            command = gnc.commands();
        }
        gnc.step(t, H);
        let acting = command;
        if !G::READ_BEFORE_STEP {
            command = gnc.commands();
        }
        let torque_plant = gnc_to_plant() * Vector3::new(acting[1], acting[2], acting[3]);
        plant.step(acting[0], torque_plant, H);
        lowest_height_m = lowest_height_m.min(plant.r_nue.y);
        if plant.r_nue.y <= 0.0 {
            break;
        }
    }
    Flight {
        messages: gnc.messages(),
        lowest_height_m,
    }
}

/// The time a message states it was raised at (`"...: t = 1.23 s: ..."`).
fn raised_at(message: &str) -> f64 {
    let after = message.split("t = ").nth(1).expect("a time");
    after.split(' ').next().unwrap().parse().expect("a number")
}

/// The message saying `says`, raised within 2 s of the mistake (present from the start);
/// no message twice.
fn assert_named<G: Gnc>(mistake: Mistake, says: &str) {
    let flight = fly::<G>(mistake, 6.0);
    let found = flight
        .messages
        .iter()
        .find(|m| m.contains(says))
        .unwrap_or_else(|| panic!("{mistake:?}: nothing says {says:?}: {:#?}", flight.messages));
    let at = raised_at(found);
    assert!(at <= 2.0, "{mistake:?} named at t = {at} s: {found}");
    let mut unique = flight.messages.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(
        unique.len(),
        flight.messages.len(),
        "{:#?}",
        flight.messages
    );
    eprintln!("{mistake:?}: t = {at} s: {found}");
}

fn correctly_wired_raises_nothing<G: Gnc>() {
    // GIVEN the plant wired through the constant rotation, the GNC's parameters its own
    // WHEN it flies the hover, the roll to 150 deg and the start of the descent
    let flight = fly::<G>(Mistake::None, 40.0);
    // THEN nothing is logged, and it stays aloft
    assert!(flight.messages.is_empty(), "{:#?}", flight.messages);
    assert!(flight.lowest_height_m > 700.0, "{}", flight.lowest_height_m);
}

fn each_mistake_is_named_within_two_seconds<G: Gnc>() {
    assert_named::<G>(Mistake::ScalarLast, "the quaternion looks scalar-last");
    assert_named::<G>(
        Mistake::Conjugate,
        "the quaternion looks like its conjugate",
    );
    assert_named::<G>(Mistake::DegreesPerSecond, "body rates look like deg/s");
    assert_named::<G>(Mistake::Enu, "look like ENU");
    assert_named::<G>(Mistake::EarthGravity, "implies gravity 1.6");
    assert_named::<G>(Mistake::InertiaThousandfold, "the plant's inertia looks");
    assert_named::<G>(Mistake::WeightAboveThrustMax, "cannot hover");
}

#[test]
fn fmi2_correctly_wired_raises_nothing() {
    correctly_wired_raises_nothing::<Fmi2>();
}

#[test]
fn fmi3_correctly_wired_raises_nothing() {
    correctly_wired_raises_nothing::<Fmi3>();
}

#[test]
fn fmi2_each_mistake_is_named_within_two_seconds() {
    each_mistake_is_named_within_two_seconds::<Fmi2>();
}

#[test]
fn fmi3_each_mistake_is_named_within_two_seconds() {
    each_mistake_is_named_within_two_seconds::<Fmi3>();
}
