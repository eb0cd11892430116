//! The random numbers of the Start-Kit's delays, drawn exactly as its build draws them: the
//! standard `std::mt19937` and the distributions of GNU libstdc++ 12 (x86-64), so that a
//! problem's `delayConfig` gives the same delays here as in the Start-Kit.
//!
//! | libstdc++ | here |
//! | --- | --- |
//! | `std::mt19937` | [`Mt19937`] |
//! | `generate_canonical<double, 53>` (two words, the first the low part) | [`Mt19937::canonical`] |
//! | `uniform_int_distribution<int>` (Lemire's nearly divisionless method) | [`Mt19937::below`] |
//! | `bernoulli_distribution` | `canonical() < p` |
//! | `normal_distribution<double>` (Marsaglia's polar method, one value kept) | [`Normal`] |
//! | `poisson_distribution<int>` (the product method below 12, Devroye's rejection above) | [`poisson`] |
//! | `std::shuffle` (two positions per draw while n² fits in 32 bits) | [`shuffle`] |
//!
//! `log`, `exp` and `sqrt` are the platform's (glibc's on Linux, as the Start-Kit's); `lgamma`
//! is only needed at whole numbers, where [`ln_gamma`] gives glibc's bits (checked on every
//! whole number below 3,000,000).

/// The 32-bit Mersenne Twister, `std::mt19937`.
pub struct Mt19937 {
    mt: [u32; 624],
    i: usize,
}

impl Mt19937 {
    /// Seeded as `std::mt19937(seed)`.
    #[must_use]
    pub fn new(seed: u32) -> Mt19937 {
        let mut mt = [0u32; 624];
        mt[0] = seed;
        for i in 1..624 {
            mt[i] = 1_812_433_253u32.wrapping_mul(mt[i - 1] ^ (mt[i - 1] >> 30)).wrapping_add(i as u32);
        }
        Mt19937 { mt, i: 624 }
    }

    fn twist(&mut self) {
        for k in 0..624 {
            let y = (self.mt[k] & 0x8000_0000) | (self.mt[(k + 1) % 624] & 0x7fff_ffff);
            self.mt[k] = self.mt[(k + 397) % 624] ^ (y >> 1) ^ if y & 1 == 1 { 0x9908_b0df } else { 0 };
        }
        self.i = 0;
    }

    /// The next word.
    pub fn word(&mut self) -> u32 {
        if self.i >= 624 {
            self.twist();
        }
        let mut y = self.mt[self.i];
        self.i += 1;
        y ^= y >> 11;
        y ^= (y << 7) & 0x9d2c_5680;
        y ^= (y << 15) & 0xefc6_0000;
        y ^ (y >> 18)
    }

    /// A double in `[0, 1)` from two words (`generate_canonical<double, 53>`).
    pub fn canonical(&mut self) -> f64 {
        let mut sum = f64::from(self.word());
        sum += f64::from(self.word()) * 4_294_967_296.0;
        let r = sum / 18_446_744_073_709_551_616.0;
        if r >= 1.0 {
            1.0 - f64::EPSILON / 2.0
        } else {
            r
        }
    }

    /// A whole number in `[0, range)`, `1 <= range < 2^32` (libstdc++'s `_S_nd`).
    pub fn below(&mut self, range: u32) -> u32 {
        let r = u64::from(range);
        let mut prod = u64::from(self.word()) * r;
        let mut low = prod as u32;
        if low < range {
            let threshold = range.wrapping_neg() % range;
            while low < threshold {
                prod = u64::from(self.word()) * r;
                low = prod as u32;
            }
        }
        (prod >> 32) as u32
    }

    /// A whole number in `[a, b]` (`uniform_int_distribution<int>(a, b)`).
    pub fn uniform(&mut self, a: i32, b: i32) -> i32 {
        let range = (i64::from(b) - i64::from(a) + 1) as u32;
        (i64::from(a) + i64::from(self.below(range))) as i32
    }
}

/// `normal_distribution<double>`: Marsaglia's polar method, keeping the second value of a pair
/// for the next draw.
#[derive(Default)]
pub struct Normal {
    saved: Option<f64>,
}

impl Normal {
    /// A draw of mean `mean` and standard deviation `sd`.
    pub fn draw(&mut self, g: &mut Mt19937, mean: f64, sd: f64) -> f64 {
        let z = if let Some(z) = self.saved.take() {
            z
        } else {
            let (x, y, r2) = loop {
                let x = 2.0 * g.canonical() - 1.0;
                let y = 2.0 * g.canonical() - 1.0;
                let r2 = x * x + y * y;
                if !(r2 > 1.0 || r2 == 0.0) {
                    break (x, y, r2);
                }
            };
            let mult = (-2.0 * r2.ln() / r2).sqrt();
            self.saved = Some(x * mult);
            y * mult
        };
        z * sd + mean
    }
}

/// `std::round` and `std::lround`: halves away from zero.
#[must_use]
pub fn round_half_away(v: f64) -> f64 {
    v.round()
}

/// `lgamma(k)` for a whole number `k >= 1`, as glibc computes it (its `x < 8` branch is the
/// logarithm of `(k - 1)!`, its `x >= 8` branch Stirling's series with fdlibm's coefficients).
#[must_use]
#[allow(clippy::excessive_precision)] // fdlibm's digits, as glibc writes them
pub fn ln_gamma(k: f64) -> f64 {
    const W: [f64; 7] = [
        4.189_385_332_046_727_250_52e-01,
        8.333_333_333_333_296_788_49e-02,
        -2.777_777_777_287_755_364_70e-03,
        7.936_505_586_430_195_585_00e-04,
        -5.951_875_574_503_399_631_35e-04,
        8.363_399_189_962_821_391_26e-04,
        -1.630_929_340_965_752_739_89e-03,
    ];
    if k <= 2.0 {
        return 0.0;
    }
    if k < 8.0 {
        let mut z = 1.0;
        for f in (2..k as i32).rev() {
            z *= f64::from(f);
        }
        return z.ln();
    }
    let t = k.ln();
    let z = 1.0 / k;
    let y = z * z;
    let w = W[0] + z * (W[1] + y * (W[2] + y * (W[3] + y * (W[4] + y * (W[5] + y * W[6])))));
    (k - 0.5) * (t - 1.0) + w
}

/// A draw of `poisson_distribution<int>(mean)`, made afresh for the draw.
pub fn poisson(g: &mut Mt19937, mean: f64) -> i64 {
    if mean < 12.0 {
        let threshold = (-mean).exp();
        let mut x = 0i64;
        let mut prod = 1.0;
        loop {
            prod *= g.canonical();
            x += 1;
            if prod <= threshold {
                return x - 1;
            }
        }
    }
    devroye(g, mean)
}

/// The rejection method libstdc++ uses for a mean of 12 or more.
#[allow(clippy::unreadable_literal, clippy::excessive_precision)]
#[allow(clippy::approx_constant)] // the digits of libstdc++'s source
fn devroye(g: &mut Mt19937, mean: f64) -> i64 {
    const PI_4: f64 = 0.7853981633974483096156608458198757;
    const SPI_2: f64 = 1.2533141373155002512078826424055226;
    const E178: f64 = 1.0129030479320018583185514777512983;
    const ONE78: f64 = 0.0128205128205128205128205128205128;
    let m = mean.floor();
    let lm_thr = mean.ln();
    let lfm = ln_gamma(m + 1.0);
    let sm = m.sqrt();
    let dx = (2.0 * m * (32.0 * m / PI_4).ln()).sqrt();
    let d = round_half_away(6.0f64.max(m.min(dx)));
    let cx = 2.0 * m + d;
    let scx = (cx / 2.0).sqrt();
    let one_cx = 1.0 / cx;
    let c2b = (PI_4 * cx).sqrt() * one_cx.exp();
    let cb = 2.0 * cx * (-d * one_cx * (1.0 + d / 2.0)).exp() / d;
    let naf = (1.0 - f64::EPSILON) / 2.0;
    let ithr = 2147483647.0 + naf;
    let c1 = sm * SPI_2;
    let c2 = c2b + c1;
    let c3 = c2 + 1.0;
    let c4 = c3 + 1.0;
    let c5 = c4 + E178;
    let c = cb + c5;
    let two_cx = 2.0 * (2.0 * m + d);
    let mut nd = Normal::default();
    loop {
        let u = c * g.canonical();
        let e = -(1.0 - g.canonical()).ln();
        let mut w = 0.0;
        let x;
        if u <= c1 {
            let n = nd.draw(g, 0.0, 1.0);
            let y = -n.abs() * sm - 1.0;
            x = y.floor();
            w = -n * n / 2.0;
            if x < -m {
                continue;
            }
        } else if u <= c2 {
            let n = nd.draw(g, 0.0, 1.0);
            let y = 1.0 + n.abs() * scx;
            x = y.ceil();
            w = y * (2.0 - y) * one_cx;
            if x > d {
                continue;
            }
        } else if u <= c3 {
            x = -1.0;
        } else if u <= c4 {
            x = 0.0;
        } else if u <= c5 {
            x = 1.0;
            w = ONE78;
        } else {
            let v = -(1.0 - g.canonical()).ln();
            let y = d + v * two_cx / d;
            x = y.ceil();
            w = -d * one_cx * (1.0 + y / 2.0);
        }
        let reject = w - e - x * lm_thr > lfm - ln_gamma(x + m + 1.0) || x + m >= ithr;
        if !reject {
            return (x + m + naf) as i64;
        }
    }
}

/// `std::shuffle(v.begin(), v.end(), g)`.
pub fn shuffle(g: &mut Mt19937, v: &mut [u32]) {
    let n = v.len();
    if n < 2 {
        return;
    }
    if u64::from(u32::MAX) / n as u64 >= n as u64 {
        let mut i = 1;
        if n % 2 == 0 {
            let j = g.below(2) as usize;
            v.swap(1, j);
            i = 2;
        }
        while i != n {
            let (b0, b1) = (i as u32 + 1, i as u32 + 2);
            let x = g.below(b0 * b1);
            v.swap(i, (x / b1) as usize);
            i += 1;
            v.swap(i, (x % b1) as usize);
            i += 1;
        }
    } else {
        for i in 1..n {
            let j = g.below(i as u32 + 1) as usize;
            v.swap(i, j);
        }
    }
}
