//! Hairer's DOP853 (Hairer, Nørsett & Wanner, *Solving ODEs I*, Sec. II.10; the Fortran code
//! DOP853): the explicit Runge–Kutta method of order 8 of Dormand and Prince with 12 stages,
//! its embedded error estimators of orders 5 and 3 combined as the code does, its continuous
//! extension of order 7 (three extra stages per accepted step), Hairer's PI controller with
//! the code's constants and his stiffness test.
//!
//! Evaluations, as the code counts them: 11 per attempt (stages 2..12; stage 1 is the last
//! step's `f(y1)`), and per accepted step one more for `f(y1)` and three for the dense output
//! ([`Stepper::complete`]), so 15 per accepted step and 11 per rejected one.
//!
//! Error estimate (the code's): with `sk = atol + rtol max(|y0|, |y1|)`,
//! `e5 = h sum er_i k_i` (order 5) and `e3 = h (sum b_i k_i - bhh1 k1 - bhh2 k9 - bhh3 k12)`
//! (order 3), `err = E5 / sqrt(n (E5 + 0.01 E3))` with `E5 = sum (e5/sk)^2`,
//! `E3 = sum (e3/sk)^2`: algebraically the code's `|h| err * sqrt(1 / (n deno))` with its
//! unscaled sums ([`crate::norm`]). The estimate behaves like `O(h^8)`.
//!
//! The coefficients are typed from the published digits (the code DOP853); the tests at the
//! bottom check every order condition up to order 8 (the 200 rooted trees), those of the
//! embedded estimators, the nodes, and compute the method's stability boundary.

// The digits as they are published.
#![allow(clippy::excessive_precision)]

use crate::controller::PiController;
use crate::dense::DenseOutput;
use crate::options::SolverOptions;
use crate::stepper::{Attempt, StepFailure, Stepper};
use crate::system::OdeSystem;
use crate::State;

// Nodes.
pub(crate) const C2: f64 = 0.526001519587677318785587544488e-01;
pub(crate) const C3: f64 = 0.789002279381515978178381316732e-01;
pub(crate) const C4: f64 = 0.118350341907227396726757197510e+00;
pub(crate) const C5: f64 = 0.281649658092772603273242802490e+00;
pub(crate) const C6: f64 = 0.333333333333333333333333333333e+00;
pub(crate) const C7: f64 = 0.25e+00;
pub(crate) const C8: f64 = 0.307692307692307692307692307692e+00;
pub(crate) const C9: f64 = 0.651282051282051282051282051282e+00;
pub(crate) const C10: f64 = 0.6e+00;
pub(crate) const C11: f64 = 0.857142857142857142857142857142e+00;
// c12 = 1 (stage 12 is at t + h).
pub(crate) const C14: f64 = 0.1e+00;
pub(crate) const C15: f64 = 0.2e+00;
pub(crate) const C16: f64 = 0.777777777777777777777777777778e+00;

// Weights of the solution of order 8 (b2..b5 = 0).
pub(crate) const B1: f64 = 5.42937341165687622380535766363e-2;
pub(crate) const B6: f64 = 4.45031289275240888144113950566e0;
pub(crate) const B7: f64 = 1.89151789931450038304281599044e0;
pub(crate) const B8: f64 = -5.8012039600105847814672114227e0;
pub(crate) const B9: f64 = 3.1116436695781989440891606237e-1;
pub(crate) const B10: f64 = -1.52160949662516078556178806805e-1;
pub(crate) const B11: f64 = 2.01365400804030348374776537501e-1;
pub(crate) const B12: f64 = 4.47106157277725905176885569043e-2;

// The third-order estimator's weights on k1, k9, k12.
pub(crate) const BHH1: f64 = 0.244094488188976377952755905512e+00;
pub(crate) const BHH2: f64 = 0.733846688281611857341361741547e+00;
pub(crate) const BHH3: f64 = 0.220588235294117647058823529412e-01;

// The fifth-order estimator's weights (b - b5) on k1, k6..k12.
pub(crate) const ER1: f64 = 0.1312004499419488073250102996e-01;
pub(crate) const ER6: f64 = -0.1225156446376204440720569753e+01;
pub(crate) const ER7: f64 = -0.4957589496572501915214079952e+00;
pub(crate) const ER8: f64 = 0.1664377182454986536961530415e+01;
pub(crate) const ER9: f64 = -0.3503288487499736816886487290e+00;
pub(crate) const ER10: f64 = 0.3341791187130174790297318841e+00;
pub(crate) const ER11: f64 = 0.8192320648511571246570742613e-01;
pub(crate) const ER12: f64 = -0.2235530786388629525884427845e-01;

pub(crate) const A21: f64 = 5.26001519587677318785587544488e-2;
pub(crate) const A31: f64 = 1.97250569845378994544595329183e-2;
pub(crate) const A32: f64 = 5.91751709536136983633785987549e-2;
pub(crate) const A41: f64 = 2.95875854768068491816892993775e-2;
pub(crate) const A43: f64 = 8.87627564304205475450678981324e-2;
pub(crate) const A51: f64 = 2.41365134159266685502369798665e-1;
pub(crate) const A53: f64 = -8.84549479328286085344864962717e-1;
pub(crate) const A54: f64 = 9.24834003261792003115737966543e-1;
pub(crate) const A61: f64 = 3.7037037037037037037037037037e-2;
pub(crate) const A64: f64 = 1.70828608729473871279604482173e-1;
pub(crate) const A65: f64 = 1.25467687566822425016691814123e-1;
pub(crate) const A71: f64 = 3.7109375e-2;
pub(crate) const A74: f64 = 1.70252211019544039314978060272e-1;
pub(crate) const A75: f64 = 6.02165389804559606850219397283e-2;
pub(crate) const A76: f64 = -1.7578125e-2;
pub(crate) const A81: f64 = 3.70920001185047927108779319836e-2;
pub(crate) const A84: f64 = 1.70383925712239993810214054705e-1;
pub(crate) const A85: f64 = 1.07262030446373284651809199168e-1;
pub(crate) const A86: f64 = -1.53194377486244017527936158236e-2;
pub(crate) const A87: f64 = 8.27378916381402288758473766002e-3;
pub(crate) const A91: f64 = 6.24110958716075717114429577812e-1;
pub(crate) const A94: f64 = -3.36089262944694129406857109825e0;
pub(crate) const A95: f64 = -8.68219346841726006818189891453e-1;
pub(crate) const A96: f64 = 2.75920996994467083049415600797e1;
pub(crate) const A97: f64 = 2.01540675504778934086186788979e1;
pub(crate) const A98: f64 = -4.34898841810699588477366255144e1;
pub(crate) const A101: f64 = 4.77662536438264365890433908527e-1;
pub(crate) const A104: f64 = -2.48811461997166764192642586468e0;
pub(crate) const A105: f64 = -5.90290826836842996371446475743e-1;
pub(crate) const A106: f64 = 2.12300514481811942347288949897e1;
pub(crate) const A107: f64 = 1.52792336328824235832596922938e1;
pub(crate) const A108: f64 = -3.32882109689848629194453265587e1;
pub(crate) const A109: f64 = -2.03312017085086261358222928593e-2;
pub(crate) const A111: f64 = -9.3714243008598732571704021658e-1;
pub(crate) const A114: f64 = 5.18637242884406370830023853209e0;
pub(crate) const A115: f64 = 1.09143734899672957818500254654e0;
pub(crate) const A116: f64 = -8.14978701074692612513997267357e0;
pub(crate) const A117: f64 = -1.85200656599969598641566180701e1;
pub(crate) const A118: f64 = 2.27394870993505042818970056734e1;
pub(crate) const A119: f64 = 2.49360555267965238987089396762e0;
pub(crate) const A1110: f64 = -3.0467644718982195003823669022e0;
pub(crate) const A121: f64 = 2.27331014751653820792359768449e0;
pub(crate) const A124: f64 = -1.05344954667372501984066689879e1;
pub(crate) const A125: f64 = -2.00087205822486249909675718444e0;
pub(crate) const A126: f64 = -1.79589318631187989172765950534e1;
pub(crate) const A127: f64 = 2.79488845294199600508499808837e1;
pub(crate) const A128: f64 = -2.85899827713502369474065508674e0;
pub(crate) const A129: f64 = -8.87285693353062954433549289258e0;
pub(crate) const A1210: f64 = 1.23605671757943030647266201528e1;
pub(crate) const A1211: f64 = 6.43392746015763530355970484046e-1;

// The three stages of the continuous extension (stage 13 is f(y1)).
pub(crate) const A141: f64 = 5.61675022830479523392909219681e-2;
pub(crate) const A147: f64 = 2.53500210216624811088794765333e-1;
pub(crate) const A148: f64 = -2.46239037470802489917441475441e-1;
pub(crate) const A149: f64 = -1.24191423263816360469010140626e-1;
pub(crate) const A1410: f64 = 1.5329179827876569731206322685e-1;
pub(crate) const A1411: f64 = 8.20105229563468988491666602057e-3;
pub(crate) const A1412: f64 = 7.56789766054569976138603589584e-3;
pub(crate) const A1413: f64 = -8.298e-3;
pub(crate) const A151: f64 = 3.18346481635021405060768473261e-2;
pub(crate) const A156: f64 = 2.83009096723667755288322961402e-2;
pub(crate) const A157: f64 = 5.35419883074385676223797384372e-2;
pub(crate) const A158: f64 = -5.49237485713909884646569340306e-2;
pub(crate) const A1511: f64 = -1.08347328697249322858509316994e-4;
pub(crate) const A1512: f64 = 3.82571090835658412954920192323e-4;
pub(crate) const A1513: f64 = -3.40465008687404560802977114492e-4;
pub(crate) const A1514: f64 = 1.41312443674632500278074618366e-1;
pub(crate) const A161: f64 = -4.28896301583791923408573538692e-1;
pub(crate) const A166: f64 = -4.69762141536116384314449447206e0;
pub(crate) const A167: f64 = 7.68342119606259904184240953878e0;
pub(crate) const A168: f64 = 4.06898981839711007970213554331e0;
pub(crate) const A169: f64 = 3.56727187455281109270669543021e-1;
pub(crate) const A1613: f64 = -1.39902416515901462129418009734e-3;
pub(crate) const A1614: f64 = 2.9475147891527723389556272149e0;
pub(crate) const A1615: f64 = -9.15095847217987001081870187138e0;

// Dense output: rows 4..7 of the code's `d` on k1, k6..k16.
pub(crate) const D41: f64 = -0.84289382761090128651353491142e+01;
pub(crate) const D46: f64 = 0.56671495351937776962531783590e+00;
pub(crate) const D47: f64 = -0.30689499459498916912797304727e+01;
pub(crate) const D48: f64 = 0.23846676565120698287728149680e+01;
pub(crate) const D49: f64 = 0.21170345824450282767155149946e+01;
pub(crate) const D410: f64 = -0.87139158377797299206789907490e+00;
pub(crate) const D411: f64 = 0.22404374302607882758541771650e+01;
pub(crate) const D412: f64 = 0.63157877876946881815570249290e+00;
pub(crate) const D413: f64 = -0.88990336451333310820698117400e-01;
pub(crate) const D414: f64 = 0.18148505520854727256656404962e+02;
pub(crate) const D415: f64 = -0.91946323924783554000451984436e+01;
pub(crate) const D416: f64 = -0.44360363875948939664310572000e+01;

pub(crate) const D51: f64 = 0.10427508642579134603413151009e+02;
pub(crate) const D56: f64 = 0.24228349177525818288430175319e+03;
pub(crate) const D57: f64 = 0.16520045171727028198505394887e+03;
pub(crate) const D58: f64 = -0.37454675472269020279518312152e+03;
pub(crate) const D59: f64 = -0.22113666853125306036270938578e+02;
pub(crate) const D510: f64 = 0.77334326684722638389603898808e+01;
pub(crate) const D511: f64 = -0.30674084731089398182061213626e+02;
pub(crate) const D512: f64 = -0.93321305264302278729567221706e+01;
pub(crate) const D513: f64 = 0.15697238121770843886131091075e+02;
pub(crate) const D514: f64 = -0.31139403219565177677282850411e+02;
pub(crate) const D515: f64 = -0.93529243588444783865713862664e+01;
pub(crate) const D516: f64 = 0.35816841486394083752465898540e+02;

pub(crate) const D61: f64 = 0.19985053242002433820987653617e+02;
pub(crate) const D66: f64 = -0.38703730874935176555105901742e+03;
pub(crate) const D67: f64 = -0.18917813819516756882830838328e+03;
pub(crate) const D68: f64 = 0.52780815920542364900561016686e+03;
pub(crate) const D69: f64 = -0.11573902539959630126141871134e+02;
pub(crate) const D610: f64 = 0.68812326946963000169666922661e+01;
pub(crate) const D611: f64 = -0.10006050966910838403183860980e+01;
pub(crate) const D612: f64 = 0.77771377980534432092869265740e+00;
pub(crate) const D613: f64 = -0.27782057523535084065932004339e+01;
pub(crate) const D614: f64 = -0.60196695231264120758267380846e+02;
pub(crate) const D615: f64 = 0.84320405506677161018159903784e+02;
pub(crate) const D616: f64 = 0.11992291136182789328035130030e+02;

pub(crate) const D71: f64 = -0.25693933462703749003312586129e+02;
pub(crate) const D76: f64 = -0.15418974869023643374053993627e+03;
pub(crate) const D77: f64 = -0.23152937917604549567536039109e+03;
pub(crate) const D78: f64 = 0.35763911791061412378285349910e+03;
pub(crate) const D79: f64 = 0.93405324183624310003907691704e+02;
pub(crate) const D710: f64 = -0.37458323136451633156875139351e+02;
pub(crate) const D711: f64 = 0.10409964950896230045147246184e+03;
pub(crate) const D712: f64 = 0.29840293426660503123344363579e+02;
pub(crate) const D713: f64 = -0.43533456590011143754432175058e+02;
pub(crate) const D714: f64 = 0.96324553959188282948394950600e+02;
pub(crate) const D715: f64 = -0.39177261675615439165231486172e+02;
pub(crate) const D716: f64 = -0.14972683625798562581422125276e+03;

/// DOP853's stability boundary on the negative real axis: the `x` with `|R(-x)| = 1` for its
/// stability polynomial `R(z) = sum_j gamma_j z^j`, `gamma_j = 1/j!` up to `j = 8` and
/// `b^T A^(j-1) 1` for `j = 9..12` (computed in `tests::stability_boundary`).
pub const STABILITY_BOUNDARY: f64 = 6.393_651_522_851_909;

/// The loop's stiffness threshold on `h |lambda|` under DOP853: 0.9 of its stability boundary,
/// as [`crate::stiffness::THRESHOLD`] is of DOPRI5's (the code DOP853 itself tests 6.1).
pub const STIFFNESS_THRESHOLD: f64 = 0.9 * STABILITY_BOUNDARY;

/// `y + h (a_1 k_1 + a_2 k_2 + ...)`, the sum in the code's order, component by component.
#[inline(always)]
fn stage_input<const N: usize, const M: usize>(
    y: &State<N>,
    h: f64,
    terms: [(f64, &State<N>); M],
) -> State<N> {
    let mut out = *y;
    for n in 0..N {
        let mut acc = terms[0].1[n] * terms[0].0;
        for term in &terms[1..] {
            acc += term.1[n] * term.0;
        }
        out[n] += h * acc;
    }
    out
}

/// `a_1 k_1 + a_2 k_2 + ...`.
#[inline(always)]
fn weighted<const N: usize, const M: usize>(terms: [(f64, &State<N>); M]) -> State<N> {
    let mut out = State::<N>::zeros();
    for n in 0..N {
        let mut acc = terms[0].1[n] * terms[0].0;
        for term in &terms[1..] {
            acc += term.1[n] * term.0;
        }
        out[n] = acc;
    }
    out
}

/// DOP853 with constant coefficients. Keeps the stages of the last attempt for its error
/// estimate, dense output and stiffness test.
pub struct Dop853<const N: usize> {
    /// `k[i]` is stage `i + 1`: `k[0] = f0`, `k[1..12]` stages 2..12 of the last attempt;
    /// once it is accepted, `k[12] = f(y1)` (stage 13) and `k[13..16]` the continuous
    /// extension's stages 14..16.
    k: [State<N>; 16],
    /// Input of stage 12 (at `t + h`), for the stiffness test.
    stage12_input: State<N>,
}

impl<const N: usize> Dop853<N> {
    pub fn new() -> Self {
        Dop853 {
            k: [State::<N>::zeros(); 16],
            stage12_input: State::<N>::zeros(),
        }
    }
}

impl<const N: usize> Default for Dop853<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Stepper<N> for Dop853<N> {
    type Controller = PiController;

    fn order(&self) -> u32 {
        8
    }

    fn is_adaptive(&self) -> bool {
        true
    }

    /// The code's controller: `beta = 0`, safety 0.9, `h_new / h` within `[1/3, 6]`
    /// (`fac1 = 0.333`, `fac2 = 6`), exponent `1/8 - 0.2 beta`. The settings' four
    /// controller numbers are DOPRI5's and do not apply.
    fn controller(&self, _opts: &SolverOptions) -> PiController {
        PiController::dop853()
    }

    fn stiffness_threshold(&self) -> f64 {
        STIFFNESS_THRESHOLD
    }

    #[inline]
    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        f0: &State<N>,
        h: f64,
    ) -> Result<Attempt<N>, StepFailure> {
        let k = &mut self.k;
        k[0] = *f0;
        k[1] = sys.rhs(t + C2 * h, &stage_input(y, h, [(A21, &k[0])]));
        k[2] = sys.rhs(t + C3 * h, &stage_input(y, h, [(A31, &k[0]), (A32, &k[1])]));
        k[3] = sys.rhs(t + C4 * h, &stage_input(y, h, [(A41, &k[0]), (A43, &k[2])]));
        k[4] = sys.rhs(
            t + C5 * h,
            &stage_input(y, h, [(A51, &k[0]), (A53, &k[2]), (A54, &k[3])]),
        );
        k[5] = sys.rhs(
            t + C6 * h,
            &stage_input(y, h, [(A61, &k[0]), (A64, &k[3]), (A65, &k[4])]),
        );
        k[6] = sys.rhs(
            t + C7 * h,
            &stage_input(
                y,
                h,
                [(A71, &k[0]), (A74, &k[3]), (A75, &k[4]), (A76, &k[5])],
            ),
        );
        k[7] = sys.rhs(
            t + C8 * h,
            &stage_input(
                y,
                h,
                [
                    (A81, &k[0]),
                    (A84, &k[3]),
                    (A85, &k[4]),
                    (A86, &k[5]),
                    (A87, &k[6]),
                ],
            ),
        );
        k[8] = sys.rhs(
            t + C9 * h,
            &stage_input(
                y,
                h,
                [
                    (A91, &k[0]),
                    (A94, &k[3]),
                    (A95, &k[4]),
                    (A96, &k[5]),
                    (A97, &k[6]),
                    (A98, &k[7]),
                ],
            ),
        );
        k[9] = sys.rhs(
            t + C10 * h,
            &stage_input(
                y,
                h,
                [
                    (A101, &k[0]),
                    (A104, &k[3]),
                    (A105, &k[4]),
                    (A106, &k[5]),
                    (A107, &k[6]),
                    (A108, &k[7]),
                    (A109, &k[8]),
                ],
            ),
        );
        k[10] = sys.rhs(
            t + C11 * h,
            &stage_input(
                y,
                h,
                [
                    (A111, &k[0]),
                    (A114, &k[3]),
                    (A115, &k[4]),
                    (A116, &k[5]),
                    (A117, &k[6]),
                    (A118, &k[7]),
                    (A119, &k[8]),
                    (A1110, &k[9]),
                ],
            ),
        );
        let y12 = stage_input(
            y,
            h,
            [
                (A121, &k[0]),
                (A124, &k[3]),
                (A125, &k[4]),
                (A126, &k[5]),
                (A127, &k[6]),
                (A128, &k[7]),
                (A129, &k[8]),
                (A1210, &k[9]),
                (A1211, &k[10]),
            ],
        );
        k[11] = sys.rhs(t + h, &y12);
        self.stage12_input = y12;
        let k = &self.k;
        // The increment `sum b_i k_i`, then `y1 = y + h * increment` as the code does.
        let incr = weighted([
            (B1, &k[0]),
            (B6, &k[5]),
            (B7, &k[6]),
            (B8, &k[7]),
            (B9, &k[8]),
            (B10, &k[9]),
            (B11, &k[10]),
            (B12, &k[11]),
        ]);
        let mut y1 = *y;
        let mut err3 = State::<N>::zeros();
        for n in 0..N {
            y1[n] += h * incr[n];
            err3[n] = h * (incr[n] - BHH1 * k[0][n] - BHH2 * k[8][n] - BHH3 * k[11][n]);
        }
        let err5 = weighted([
            (ER1, &k[0]),
            (ER6, &k[5]),
            (ER7, &k[6]),
            (ER8, &k[7]),
            (ER9, &k[8]),
            (ER10, &k[9]),
            (ER11, &k[10]),
            (ER12, &k[11]),
        ]) * h;
        Ok(Attempt {
            y1,
            f1: None,
            err: Some(err5),
            err_low: Some(err3),
        })
    }

    /// `f(y1)`, the next step's first stage, and the continuous extension's three stages.
    fn complete<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        h: f64,
        a: &mut Attempt<N>,
    ) -> bool {
        let k = &mut self.k;
        k[12] = sys.rhs(t + h, &a.y1);
        a.f1 = Some(k[12]);
        k[13] = sys.rhs(
            t + C14 * h,
            &stage_input(
                y,
                h,
                [
                    (A141, &k[0]),
                    (A147, &k[6]),
                    (A148, &k[7]),
                    (A149, &k[8]),
                    (A1410, &k[9]),
                    (A1411, &k[10]),
                    (A1412, &k[11]),
                    (A1413, &k[12]),
                ],
            ),
        );
        k[14] = sys.rhs(
            t + C15 * h,
            &stage_input(
                y,
                h,
                [
                    (A151, &k[0]),
                    (A156, &k[5]),
                    (A157, &k[6]),
                    (A158, &k[7]),
                    (A1511, &k[10]),
                    (A1512, &k[11]),
                    (A1513, &k[12]),
                    (A1514, &k[13]),
                ],
            ),
        );
        k[15] = sys.rhs(
            t + C16 * h,
            &stage_input(
                y,
                h,
                [
                    (A161, &k[0]),
                    (A166, &k[5]),
                    (A167, &k[6]),
                    (A168, &k[7]),
                    (A169, &k[8]),
                    (A1613, &k[12]),
                    (A1614, &k[13]),
                    (A1615, &k[14]),
                ],
            ),
        );
        true
    }

    fn dense(
        &self,
        t: f64,
        h: f64,
        y0: &State<N>,
        f0: &State<N>,
        a: &Attempt<N>,
    ) -> DenseOutput<N> {
        let f1 =
            a.f1.as_ref()
                .expect("a DOP853 step is completed (f(y1)) before its dense output");
        let k = &self.k;
        let ydiff = a.y1 - y0;
        let bspl = f0 * h - ydiff;
        let r4 = ydiff - f1 * h - bspl;
        let row = |d: [f64; 12]| {
            weighted([
                (d[0], &k[0]),
                (d[1], &k[5]),
                (d[2], &k[6]),
                (d[3], &k[7]),
                (d[4], &k[8]),
                (d[5], &k[9]),
                (d[6], &k[10]),
                (d[7], &k[11]),
                (d[8], &k[12]),
                (d[9], &k[13]),
                (d[10], &k[14]),
                (d[11], &k[15]),
            ]) * h
        };
        let r5 = row([
            D41, D46, D47, D48, D49, D410, D411, D412, D413, D414, D415, D416,
        ]);
        let r6 = row([
            D51, D56, D57, D58, D59, D510, D511, D512, D513, D514, D515, D516,
        ]);
        let r7 = row([
            D61, D66, D67, D68, D69, D610, D611, D612, D613, D614, D615, D616,
        ]);
        let r8 = row([
            D71, D76, D77, D78, D79, D710, D711, D712, D713, D714, D715, D716,
        ]);
        DenseOutput::order7(t, h, [*y0, ydiff, bspl, r4, r5, r6, r7, r8])
    }

    fn stiffness_estimate(&self, h: f64, a: &Attempt<N>) -> Option<f64> {
        // Two evaluations at t + h: f(stage 12 input) and f(y1) (Hairer, DOP853).
        crate::stiffness::h_lambda(h, &a.y1, a.f1.as_ref()?, &self.stage12_input, &self.k[11])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Butcher tableau of the 12 stages (and the dense output's 16), from the constants.
    fn tableau() -> (Vec<f64>, Vec<Vec<f64>>) {
        let mut a = vec![vec![0.0; 16]; 16];
        let mut set = |i: usize, entries: &[(usize, f64)]| {
            for &(j, v) in entries {
                a[i - 1][j - 1] = v;
            }
        };
        set(2, &[(1, A21)]);
        set(3, &[(1, A31), (2, A32)]);
        set(4, &[(1, A41), (3, A43)]);
        set(5, &[(1, A51), (3, A53), (4, A54)]);
        set(6, &[(1, A61), (4, A64), (5, A65)]);
        set(7, &[(1, A71), (4, A74), (5, A75), (6, A76)]);
        set(8, &[(1, A81), (4, A84), (5, A85), (6, A86), (7, A87)]);
        set(
            9,
            &[(1, A91), (4, A94), (5, A95), (6, A96), (7, A97), (8, A98)],
        );
        set(
            10,
            &[
                (1, A101),
                (4, A104),
                (5, A105),
                (6, A106),
                (7, A107),
                (8, A108),
                (9, A109),
            ],
        );
        set(
            11,
            &[
                (1, A111),
                (4, A114),
                (5, A115),
                (6, A116),
                (7, A117),
                (8, A118),
                (9, A119),
                (10, A1110),
            ],
        );
        set(
            12,
            &[
                (1, A121),
                (4, A124),
                (5, A125),
                (6, A126),
                (7, A127),
                (8, A128),
                (9, A129),
                (10, A1210),
                (11, A1211),
            ],
        );
        // stage 13 is f(y1): its row is b
        set(
            13,
            &[
                (1, B1),
                (6, B6),
                (7, B7),
                (8, B8),
                (9, B9),
                (10, B10),
                (11, B11),
                (12, B12),
            ],
        );
        set(
            14,
            &[
                (1, A141),
                (7, A147),
                (8, A148),
                (9, A149),
                (10, A1410),
                (11, A1411),
                (12, A1412),
                (13, A1413),
            ],
        );
        set(
            15,
            &[
                (1, A151),
                (6, A156),
                (7, A157),
                (8, A158),
                (11, A1511),
                (12, A1512),
                (13, A1513),
                (14, A1514),
            ],
        );
        set(
            16,
            &[
                (1, A161),
                (6, A166),
                (7, A167),
                (8, A168),
                (9, A169),
                (13, A1613),
                (14, A1614),
                (15, A1615),
            ],
        );
        let c = vec![
            0.0, C2, C3, C4, C5, C6, C7, C8, C9, C10, C11, 1.0, 1.0, C14, C15, C16,
        ];
        (c, a)
    }

    /// Rooted trees up to order 8, each as the list of its children (indices of smaller trees).
    fn trees(max_order: usize) -> Vec<(usize, Vec<usize>)> {
        // (order, children); trees[0] is the single node
        let mut all: Vec<(usize, Vec<usize>)> = vec![(1, vec![])];
        for n in 2..=max_order {
            // multisets of trees (non-decreasing indices) with orders summing to n - 1
            let existing = all.len();
            let mut out = Vec::new();
            fn extend(
                all: &[(usize, Vec<usize>)],
                limit: usize,
                start: usize,
                left: usize,
                cur: &mut Vec<usize>,
                out: &mut Vec<Vec<usize>>,
            ) {
                if left == 0 {
                    out.push(cur.clone());
                    return;
                }
                for i in start..limit {
                    if all[i].0 <= left {
                        cur.push(i);
                        extend(all, limit, i, left - all[i].0, cur, out);
                        cur.pop();
                    }
                }
            }
            extend(&all, existing, 0, n - 1, &mut Vec::new(), &mut out);
            for children in out {
                all.push((n, children));
            }
        }
        all
    }

    /// `g(t)_i` for every tree (the stage vector whose weighted sum is the elementary weight)
    /// and `gamma(t)`, over the first `s` stages.
    fn elementary(s: usize, a: &[Vec<f64>], trees: &[(usize, Vec<usize>)]) -> Vec<(Vec<f64>, f64)> {
        let mut out: Vec<(Vec<f64>, f64)> = Vec::new();
        for (order, children) in trees {
            let mut g = vec![1.0; s];
            let mut gamma = *order as f64;
            for &ch in children {
                let (gc, gammac) = &out[ch];
                gamma *= gammac;
                for i in 0..s {
                    let agc: f64 = (0..s).map(|j| a[i][j] * gc[j]).sum();
                    g[i] *= agc;
                }
            }
            out.push((g, gamma));
        }
        out
    }

    #[test]
    fn tree_counts() {
        let t = trees(8);
        let count = |n: usize| t.iter().filter(|x| x.0 == n).count();
        assert_eq!(
            (1..=8).map(count).collect::<Vec<_>>(),
            [1, 1, 2, 4, 9, 20, 48, 115]
        );
    }

    #[test]
    fn nodes_are_the_row_sums() {
        let (c, a) = tableau();
        for i in 1..16 {
            let sum: f64 = a[i].iter().sum();
            assert!(
                (sum - c[i]).abs() < 1e-14,
                "row {}: {sum} vs {}",
                i + 1,
                c[i]
            );
        }
        assert!((C6 - 1.0 / 3.0).abs() < 1e-16 && (C8 - 4.0 / 13.0).abs() < 1e-16);
        assert!((C9 - 127.0 / 195.0).abs() < 1e-16 && (C11 - 6.0 / 7.0).abs() < 1e-16);
        assert!((C16 - 7.0 / 9.0).abs() < 1e-16);
    }

    #[test]
    fn order_conditions_up_to_eight() {
        let (_, a) = tableau();
        let t = trees(8);
        let el = elementary(12, &a, &t);
        let b = &a[12][..12];
        let mut worst = 0.0f64;
        for ((order, _), (g, gamma)) in t.iter().zip(&el) {
            let phi: f64 = b.iter().zip(g).map(|(b, g)| b * g).sum();
            let defect = (phi * gamma - 1.0).abs();
            worst = worst.max(defect);
            assert!(defect < 1e-12, "order {order}: defect {defect:e}");
        }
        println!("largest defect of the 200 conditions: {worst:e}");
        // The order is exactly 8: some condition of order 9 fails.
        let t9 = trees(9);
        let el9 = elementary(12, &a, &t9);
        let worst9 = t9
            .iter()
            .zip(&el9)
            .filter(|((o, _), _)| *o == 9)
            .map(|(_, (g, gamma))| {
                (b.iter().zip(g).map(|(b, g)| b * g).sum::<f64>() * gamma - 1.0).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst9 > 1e-6, "{worst9}");
    }

    #[test]
    fn embedded_estimators_are_of_orders_five_and_three() {
        let (_, a) = tableau();
        let t = trees(6);
        let el = elementary(12, &a, &t);
        let mut er = [0.0; 12];
        for (j, v) in [
            (0, ER1),
            (5, ER6),
            (6, ER7),
            (7, ER8),
            (8, ER9),
            (9, ER10),
            (10, ER11),
            (11, ER12),
        ] {
            er[j] = v;
        }
        let mut e3 = a[12][..12].to_vec();
        e3[0] -= BHH1;
        e3[8] -= BHH2;
        e3[11] -= BHH3;
        let mut fails = [false; 7];
        for ((order, _), (g, gamma)) in t.iter().zip(&el) {
            let d5: f64 = er.iter().zip(g).map(|(e, g)| e * g).sum::<f64>() * gamma;
            let d3: f64 = e3.iter().zip(g).map(|(e, g)| e * g).sum::<f64>() * gamma;
            if *order <= 5 {
                assert!(
                    d5.abs() < 1e-12,
                    "5th-order estimator, order {order}: {d5:e}"
                );
            } else if d5.abs() > 1e-6 {
                fails[*order] = true;
            }
            if *order <= 3 {
                assert!(
                    d3.abs() < 1e-12,
                    "3rd-order estimator, order {order}: {d3:e}"
                );
            } else if *order == 4 && d3.abs() > 1e-6 {
                fails[4] = true;
            }
        }
        assert!(fails[6] && fails[4], "the estimators' orders are exact");
    }

    #[test]
    fn stability_boundary() {
        // gamma_j = b^T A^(j-1) 1 of the 12-stage method
        let (_, a) = tableau();
        let b = &a[12][..12];
        let mut v = vec![1.0; 12];
        let mut gamma = vec![1.0];
        for _ in 1..=12 {
            gamma.push(b.iter().zip(&v).map(|(b, v)| b * v).sum());
            v = (0..12)
                .map(|i| (0..12).map(|j| a[i][j] * v[j]).sum())
                .collect();
        }
        let mut fact = 1.0;
        for (j, g) in gamma.iter().enumerate().take(9).skip(1) {
            fact *= j as f64;
            assert!((g * fact - 1.0).abs() < 1e-12, "gamma_{j}");
        }
        let r = |z: f64| gamma.iter().rev().fold(0.0, |acc, g| acc * z + g);
        // bisection on |R(-x)| = 1 between 5 and 7
        let (mut lo, mut hi) = (5.0, 7.0);
        assert!(r(-lo).abs() < 1.0 && r(-hi).abs() > 1.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if r(-mid).abs() < 1.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        println!("gamma 9..12: {:?}; boundary {lo:.15}", &gamma[9..]);
        // stable everywhere on [-boundary, 0]
        for i in 1..=1000 {
            assert!(r(-lo * i as f64 / 1000.0).abs() <= 1.0 + 1e-12);
        }
        assert!(
            (lo - STABILITY_BOUNDARY).abs() < 1e-12,
            "{lo} vs {STABILITY_BOUNDARY}"
        );
        assert!((STIFFNESS_THRESHOLD - 0.9 * lo).abs() < 1e-12);
    }
}
