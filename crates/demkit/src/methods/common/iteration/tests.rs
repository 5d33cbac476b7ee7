//! Tests of the shared iteration on scalar flows whose moves are known exactly.

use super::*;

/// The measure of the scalar test flows: stopping quantity and merit |x − 1|.
fn distance_to_one(x: f64) -> Measured<()> {
    Measured {
        error: (x - 1.0).abs(),
        merit: (x - 1.0).abs(),
        data: (),
    }
}

/// A scalar "map" x > 0 whose stopping quantity is |x − 1| (and so is its merit): the flow
/// moves it towards 1 by the fraction `h` of the distance, overshooting when `h > 1`.
struct Toward {
    /// Fraction of an asked step actually taken.
    fraction: f64,
}

impl Flow for Toward {
    type Map = f64;
    type Data = ();
    fn measure(&mut self, x: &f64) -> Result<Measured<()>> {
        Ok(distance_to_one(*x))
    }
    fn step_cap(&self, _m: &Measured<()>) -> f64 {
        4.0
    }
    fn advance(&mut self, x: &f64, _m: &Measured<()>, h: f64) -> Result<Moved<f64>> {
        let t = h * self.fraction;
        Ok(Moved {
            map: x + t * (1.0 - x),
            fraction: self.fraction,
        })
    }
}

fn rules(step: Step) -> Rules {
    Rules {
        epsilon: 1e-6,
        max_iter: 100,
        step,
        stationary: Some(Stationary::Best {
            window: 5,
            min_gain: 0.02,
        }),
        keep: Keep::Best,
    }
}

#[test]
fn a_fixed_step_contracts_geometrically_and_stops_at_the_tolerance() {
    let mut flow = Toward { fraction: 1.0 };
    let mut seen = Vec::new();
    let out = iterate(&mut flow, 3.0, &rules(Step::Fixed(0.5)), &mut |p| {
        seen.push(p.error)
    })
    .unwrap();
    assert_eq!(out.stop_reason, StopReason::Tolerance);
    // |x − 1| halves every step: 2 · 2^−k < 1e-6 first at k = 21.
    assert_eq!(out.iterations, 21);
    assert_eq!(out.history, seen);
    assert!((out.history[0] - 1.0).abs() < 1e-15);
    assert!((out.map - 1.0).abs() < 1e-6);
}

#[test]
fn an_adaptive_step_undoes_overshoots_and_halves() {
    // The cap 4 overshoots to x = 1 − 3·2 = −5 (worse): undone, the step halved to 2
    // lands on −1 (worse again), then 1 lands exactly.
    let mut flow = Toward { fraction: 1.0 };
    let out = iterate(&mut flow, 3.0, &rules(Step::Adaptive), &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::Tolerance);
    assert_eq!(out.iterations, 3);
    assert_eq!(out.history, vec![2.0, 2.0, 0.0]);
    assert_eq!(out.map, 1.0);
}

#[test]
fn a_flow_that_cannot_move_is_stationary_and_the_first_map_is_kept() {
    let mut flow = Toward { fraction: 0.0 };
    let out = iterate(&mut flow, 3.0, &rules(Step::Fixed(0.5)), &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::Stationary);
    assert_eq!(out.iterations, 1);
    assert_eq!(out.map, 3.0);
    let out = iterate(&mut flow, 3.0, &rules(Step::Adaptive), &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::Stationary);
    assert_eq!(out.map, 3.0);
}

/// [`Toward`] with a small cap and a scale: each move goes the fraction `h` of the way to
/// the target, which is 1 at scale 0 and lies `offset` beyond 1 at the coarser scales
/// (`refines` of them left), so that a coarse scale stalls short of 1 until the flow
/// refines. Records every advance (from which map, how long) and every refinement.
struct Scaled {
    cap: f64,
    offset: f64,
    refines: usize,
    calls: Vec<(f64, f64)>,
    refined: usize,
}

impl Flow for Scaled {
    type Map = f64;
    type Data = ();
    fn measure(&mut self, x: &f64) -> Result<Measured<()>> {
        Ok(distance_to_one(*x))
    }
    fn step_cap(&self, _m: &Measured<()>) -> f64 {
        self.cap
    }
    fn refine(&mut self) -> Option<f64> {
        (self.refines > 0).then(|| {
            self.refines -= 1;
            self.refined += 1;
            self.offset = if self.refines == 0 {
                0.0
            } else {
                0.5 * self.offset
            };
            0.5
        })
    }
    fn advance(&mut self, x: &f64, _m: &Measured<()>, h: f64) -> Result<Moved<f64>> {
        self.calls.push((*x, h));
        let target = 1.0 - self.offset;
        Ok(Moved {
            map: x + h * (target - x),
            fraction: 1.0,
        })
    }
}

#[test]
fn a_search_tries_an_accepted_move_longer_along_its_direction() {
    // From 3 with the cap 0.05: 0.05 (x = 2.9), then 0.1, 0.2 and 0.4 from 3, each better:
    // the iteration keeps x = 3 − 0.4 · 2 = 2.2, and the next step may be RAMP_GROWTH ·
    // 0.4, capped at 0.05 again.
    let mut flow = Scaled {
        cap: 0.05,
        offset: 0.0,
        refines: 0,
        calls: Vec::new(),
        refined: 0,
    };
    let rules = Rules {
        max_iter: 2,
        ..rules(Step::Search)
    };
    let out = iterate(&mut flow, 3.0, &rules, &mut |_| {}).unwrap();
    let first: Vec<(f64, f64)> = flow.calls[..4].to_vec();
    assert_eq!(first, vec![(3.0, 0.05), (3.0, 0.1), (3.0, 0.2), (3.0, 0.4)]);
    assert!((out.history[0] - 1.2).abs() < 1e-12);
    assert!((flow.calls[4].0 - 2.2).abs() < 1e-12);
    assert_eq!(flow.calls[4].1, 0.05);
}

#[test]
fn a_search_retries_shorter_without_growing_and_refines_when_slow() {
    // The cap 4 overshoots from 3 to −5: retried from 3 at 2 (−1, no better), then at 1
    // (x = 1, exact), which is also tried twice as long (−1, worse) before the tolerance
    // ends the run.
    let mut flow = Scaled {
        cap: 4.0,
        offset: 0.0,
        refines: 0,
        calls: Vec::new(),
        refined: 0,
    };
    let out = iterate(&mut flow, 3.0, &rules(Step::Search), &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::Tolerance);
    assert_eq!(
        flow.calls,
        vec![(3.0, 4.0), (3.0, 2.0), (3.0, 1.0), (3.0, 2.0)]
    );
    assert_eq!(out.map, 1.0);

    // Stalled short of 1 at a coarse scale (the target 0.8): the flow is asked for a finer
    // scale and goes on to the tolerance; a flow that has none is stationary at 0.2.
    let scaled = |refines| Scaled {
        cap: 0.5,
        offset: 0.2,
        refines,
        calls: Vec::new(),
        refined: 0,
    };
    let mut flow = scaled(2);
    let out = iterate(&mut flow, 3.0, &rules(Step::Search), &mut |_| {}).unwrap();
    assert!(flow.refined >= 1);
    assert_eq!(out.stop_reason, StopReason::Tolerance);
    let mut flow = scaled(0);
    let out = iterate(&mut flow, 3.0, &rules(Step::Search), &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::Stationary);
    assert!((out.map - 0.8).abs() < 1e-9);
}

#[test]
fn slow_progress_is_stationary_and_the_limit_is_not_converged() {
    // 1 % of the distance per step: over 5 iterations the best improves by 4.9 %, less
    // than the 6 % asked, so the run stalls after its fifth iteration.
    let mut flow = Toward { fraction: 1.0 };
    let slow = Rules {
        stationary: Some(Stationary::Best {
            window: 5,
            min_gain: 0.06,
        }),
        ..rules(Step::Fixed(0.01))
    };
    let out = iterate(&mut flow, 3.0, &slow, &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::Stationary);
    assert_eq!(out.iterations, 5);
    let limited = Rules {
        max_iter: 3,
        ..rules(Step::Fixed(0.01))
    };
    let out = iterate(&mut flow, 3.0, &limited, &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::MaxIter);
    assert_eq!(out.iterations, 3);
}

/// A minimisation taking its own steps: its merit (the objective) x falls by the factor
/// `rate` per move; with `renew`, every second iteration leaves x as it is (the flow
/// renews its model). Its stopping quantity is infinite until x < `floor`, then 0, and it
/// shows 2x.
struct Descent {
    rate: f64,
    floor: f64,
    renew: bool,
    calls: usize,
}

impl Flow for Descent {
    type Map = f64;
    type Data = ();
    fn measure(&mut self, x: &f64) -> Result<Measured<()>> {
        Ok(Measured {
            error: if *x < self.floor { 0.0 } else { f64::INFINITY },
            merit: *x,
            data: (),
        })
    }
    fn shown(&self, m: &Measured<()>) -> f64 {
        2.0 * m.merit
    }
    fn advance(&mut self, x: &f64, _m: &Measured<()>, h: f64) -> Result<Moved<f64>> {
        assert_eq!(h, 1.0);
        self.calls += 1;
        Ok(if self.renew && self.calls.is_multiple_of(2) {
            Moved {
                map: *x,
                fraction: 0.0,
            }
        } else {
            Moved {
                map: x * self.rate,
                fraction: 1.0,
            }
        })
    }
}

fn own(min_gain: f64) -> Rules {
    Rules {
        epsilon: 1e-3,
        max_iter: 100,
        step: Step::Own,
        stationary: Some(Stationary::Decrease {
            window: 5,
            min_gain,
        }),
        keep: Keep::Last,
    }
}

#[test]
fn a_decrease_below_the_gain_over_the_window_of_moves_is_stationary() {
    // x_j = 0.99^j: over 5 moves the decrease is (0.99^−5 − 1) x_j = 0.0515 x_j, below a
    // gain of 6 %: stationary once the window is full, after the fifth move.
    let descent = |renew| Descent {
        rate: 0.99,
        floor: 0.0,
        renew,
        calls: 0,
    };
    let out = iterate(&mut descent(false), 1.0, &own(0.06), &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::Stationary);
    assert_eq!(out.iterations, 5);
    assert!((out.map - 0.99f64.powi(5)).abs() < 1e-15);
    // The history records what the flow shows (2x), not its stopping quantity.
    assert!((out.history[0] - 1.98).abs() < 1e-15);
    // Iterations that leave the map as it is neither stop the run nor count: the fifth
    // move is the ninth iteration.
    let out = iterate(&mut descent(true), 1.0, &own(0.06), &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::Stationary);
    assert_eq!(out.iterations, 9);
    assert_eq!(out.history[0], out.history[1]);
    assert!((out.map - 0.99f64.powi(5)).abs() < 1e-15);
    // Above the gain (5 %) it never stalls.
    let out = iterate(&mut descent(false), 1.0, &own(0.05), &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::MaxIter);
    assert_eq!(out.iterations, 100);
}

#[test]
fn a_flow_taking_its_own_steps_stops_on_its_stopping_quantity() {
    // x halves per move: 0.5^4 = 0.0625 is the first below the floor 0.1.
    let mut flow = Descent {
        rate: 0.5,
        floor: 0.1,
        renew: false,
        calls: 0,
    };
    let out = iterate(&mut flow, 1.0, &own(1e-3), &mut |_| {}).unwrap();
    assert_eq!(out.stop_reason, StopReason::Tolerance);
    assert_eq!(out.iterations, 4);
    assert_eq!(out.map, 0.0625);
    assert_eq!(out.history, vec![1.0, 0.5, 0.25, 0.125]);
}

#[test]
fn parameters_are_checked_by_name() {
    assert!(check_parameters(1e-3, None, 10).is_ok());
    let e = check_parameters(0.0, None, 10).unwrap_err().to_string();
    assert!(e.contains("epsilon must be positive"), "{e}");
    let e = check_parameters(1e-3, Some(f64::NAN), 10)
        .unwrap_err()
        .to_string();
    assert!(e.contains("dt must be positive"), "{e}");
    let e = check_parameters(1e-3, None, 0).unwrap_err().to_string();
    assert!(e.contains("max_iter must be at least 1"), "{e}");
}

#[test]
fn the_time_step_of_a_uniform_density_is_the_area() {
    assert_eq!(diffusion_time_step(&[2.0; 5], 3.0), 3.0);
    // min/mean = 0.5, mean/max = 2/3: the smaller.
    assert!((diffusion_time_step(&[1.0, 2.0, 3.0], 1.0) - 0.5).abs() < 1e-15);
}
