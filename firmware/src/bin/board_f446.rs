//! The cam-timing and jump predictor on a Nucleo-F446RE (STM32F446RE, Cortex-M4F at
//! 180 MHz): the same predictor as the QEMU image (the boot-time table of the chip's
//! scene, `camsim_firmware::workload::Predictor`), fed by a real index pulse.
//!
//! Boot: the alarm output is asserted (PA5 low, the safe state) before anything else;
//! the prediction table is built (tens of seconds); any failure stops here with the alarm
//! asserted. Then, forever: TIM2 capture on PA0 -> [`IndexPulse`] (core) -> a speed
//! reading -> prediction -> [`JumpAlarm`] hysteresis -> PA5. Only a vouched speed
//! ([`SpeedReading::Rpm`]) feeds its speed margin to the alarm; every other reading
//! (out of the table's range, rejected pulse, lost speed, acquisition, capture overrun)
//! feeds NaN, which asserts it, and it is released only once a vouched margin exceeds the
//! release threshold. The independent watchdog resets a stalled loop (pins reset = alarm);
//! a panic or fault drives PA5 low in the HardFault handler.
//!
//! Logs with defmt over RTT (`probe-rs run`, see `cargo board` in .cargo/config.toml).

#![no_std]
#![no_main]

use camsim_chip::{chip_alarm, CHIP_GRID, CHIP_GRID_RPM};
use camsim_core::{IndexPulse, IndexPulseConfig, JumpAlarm, Rejection, SpeedReading};
use camsim_firmware::board::f446::{
    drive_alarm_safe_from_fault, CaptureEvent, FailSafeOutput, IndexCapture, TICK_HZ,
};
use camsim_firmware::exit_failure;
use camsim_firmware::memory::{paint_stack, stack_peak_bytes, Sections};
use camsim_firmware::workload::{Predictor, SCENE_NAME};
use cortex_m_rt::{entry, exception, ExceptionFrame};
use stm32f4xx_hal::gpio::PinState;
use stm32f4xx_hal::pac;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::Config;
use stm32f4xx_hal::watchdog::IndependentWatchdog;

/// Core clock: the F446's maximum (APB1 45 MHz, TIM2 90 MHz).
const SYSCLK_HZ: u32 = 180_000_000;
/// HSE: the Nucleo-64's default clock input, 8 MHz from the ST-LINK's crystal (MCO, in
/// bypass mode). The capture timer's clock is the speed's reference: a crystal is good to
/// about 50 ppm (0.035 rpm at 700 rpm); the internal HSI only to 1 % at 25 °C (7 rpm) and
/// several % over temperature.
const HSE_HZ: u32 = 8_000_000;

/// Slowest speed the boot table covers, rpm (its first grid speed, rounded up).
const RANGE_MIN_RPM: u32 = {
    let x = CHIP_GRID_RPM[0];
    let t = x as u32;
    if (t as f64) < x {
        t + 1
    } else {
        t
    }
};
/// Fastest speed the boot table covers, rpm (its last grid speed, rounded down).
const RANGE_MAX_RPM: u32 = CHIP_GRID_RPM[CHIP_GRID - 1] as u32;
/// Fastest speed the machine can turn, rpm: twice the table's top (a shorter period is noise).
const LIMIT_RPM: u32 = 2 * RANGE_MAX_RPM;
/// Below half the table's slowest speed the speed counts as lost (one such revolution
/// without a pulse).
const LOST_RPM: u32 = RANGE_MIN_RPM / 2;
/// A period under this share of the last one is a bounce, %.
const BOUNCE_PERCENT: u32 = 25;
/// Consecutive periods agree within this share, % (a cam shaft's speed changes less per
/// revolution; a larger step is believed after one confirming revolution).
const MAX_CHANGE_PERCENT: u32 = 25;
/// Independent watchdog timeout, ms (the loop feeds it every few microseconds).
const WATCHDOG_MS: u32 = 500;
/// A status line this often, capture ticks (10 s).
const STATUS_TICKS: u32 = 10 * TICK_HZ;

/// Why the alarm is asserted (or not).
#[derive(Clone, Copy, Debug, PartialEq, Eq, defmt::Format)]
enum Cause {
    /// Not enough consistent pulses yet.
    Acquiring,
    /// A vouched speed: the alarm follows its speed margin (hysteresis).
    Margin,
    /// A measured speed outside the table's range.
    OutOfRange,
    /// A pulse was rejected (noise, bounce, step).
    Rejected,
    /// No pulse for a revolution at the slowest measured speed.
    Lost,
    /// The capture hardware lost an edge.
    CaptureOverrun,
}

/// Counters for the status line.
#[derive(Clone, Copy, Debug, Default, defmt::Format)]
struct Counts {
    vouched: u32,
    out_of_range: u32,
    rejected: u32,
    lost: u32,
    overruns: u32,
}

/// A short name of a core error for the log (core::fmt would cost ~20 KB of flash).
fn error_name(e: &camsim_core::Error) -> &'static str {
    use camsim_core::Error as E;
    match e {
        E::InvalidParameter { field, .. } => field,
        E::Capacity { what, .. } => what,
        E::StepSizeUnderflow { .. } => "step size underflow",
        E::NonFinite { .. } => "non-finite state",
        E::StepBudgetExceeded { .. } => "step budget exceeded",
        E::NoConvergence { what, .. } => what,
        _ => "other error",
    }
}

/// Stops with the alarm asserted: logs why, then the failure path (HardFault: probe-rs
/// reports it; without a probe the handler keeps PA5 low and the core parked).
fn fail(why: &str) -> ! {
    drive_alarm_safe_from_fault();
    defmt::error!("alarm asserted (PA5 low), stopped: {=str}", why);
    exit_failure()
}

#[entry]
fn main() -> ! {
    // First: paint the free stack so its peak can be read back.
    paint_stack();

    let Some(dp) = pac::Peripherals::take() else {
        fail("device peripherals already taken")
    };
    // Why the last reset happened (a watchdog reset means the loop had stalled).
    let csr = dp.RCC.csr().read();
    let (by_watchdog, by_pin, by_power) = (
        csr.wdgrstf().bit_is_set(),
        csr.padrstf().bit_is_set(),
        csr.porrstf().bit_is_set(),
    );
    dp.RCC.csr().modify(|_, w| w.rmvf().set_bit());

    let mut rcc = dp.RCC.constrain();
    let gpioa = dp.GPIOA.split(&mut rcc);
    // The alarm output first, asserted (LOW) from the moment it is an output.
    let Ok(mut out) = FailSafeOutput::new(gpioa.pa5.into_push_pull_output_in_state(PinState::Low));
    defmt::info!(
        "clock: HSE {=u32} Hz from the ST-LINK (bypass) -> {=u32} Hz (a hang here: no HSE, check SB16/SB50)",
        HSE_HZ,
        SYSCLK_HZ
    );
    let mut rcc = rcc.freeze(
        Config::hse(HSE_HZ.Hz())
            .bypass_hse_oscillator()
            .sysclk(SYSCLK_HZ.Hz()),
    );
    let mut capture = IndexCapture::new(dp.TIM2, gpioa.pa0, &mut rcc);
    let tick_hz = capture.tick_hz();

    let sections = Sections::get();
    defmt::info!(
        "board=nucleo-f446re sysclk_hz={=u32} tick_hz={=u32} capture=PA0 (TIM2_CH1, falling edge) alarm=PA5 (LD2 lit: speed vouched, margin fine; dark: alarm asserted, the safe state)",
        rcc.clocks.sysclk().raw(),
        tick_hz
    );
    defmt::info!(
        "reset watchdog={=bool} pin={=bool} power={=bool}; flash_bytes={=u32} ram_static_bytes={=u32}",
        by_watchdog,
        by_pin,
        by_power,
        sections.flash_bytes(),
        sections.ram_static_bytes()
    );
    if tick_hz != TICK_HZ {
        fail("TIM2 does not tick at 1 MHz (clock configuration)")
    }

    // Boot: the prediction table over the scene's speed grid (the alarm stays asserted).
    defmt::info!(
        "scene={=str}; alarm asserted (PA5 low): booting, building the prediction table",
        SCENE_NAME
    );
    let t0 = capture.now();
    let predictor = match Predictor::boot() {
        Ok(p) => p,
        Err(e) => {
            defmt::error!("boot: table build failed: {=str}", error_name(&e));
            fail("boot failed")
        }
    };
    let boot_ms = capture.now().wrapping_sub(t0) / (TICK_HZ / 1000);
    let table = &predictor.table;
    for (rpm, s) in table.rpm.iter().zip(table.at.iter()) {
        defmt::info!(
            "table rpm={=f32} min_force_lb={=f32} jumped={=bool}",
            *rpm,
            s.min_contact_force,
            s.jumped
        );
    }
    match table.jump_rpm {
        Some(j) => defmt::info!("jump_onset_rpm={=f32} boot_ms={=u32}", j, boot_ms),
        None => defmt::info!("jump_onset_rpm=none boot_ms={=u32}", boot_ms),
    }

    let mut pulse = match IndexPulse::<f32>::new(IndexPulseConfig {
        tick_hz,
        min_rpm: RANGE_MIN_RPM,
        max_rpm: RANGE_MAX_RPM,
        limit_rpm: LIMIT_RPM,
        lost_rpm: LOST_RPM,
        bounce_percent: BOUNCE_PERCENT,
        max_change_percent: MAX_CHANGE_PERCENT,
    }) {
        Ok(p) => p,
        Err(e) => {
            defmt::error!("index pulse configuration: {=str}", error_name(&e));
            fail("invalid index pulse configuration")
        }
    };
    let mut alarm: JumpAlarm<f32> = match chip_alarm() {
        Ok(a) => a,
        Err(_) => fail("invalid alarm thresholds"),
    };
    // The boot state: asserted until a vouched margin exceeds the release threshold.
    alarm.update(f32::NAN);
    defmt::info!(
        "index pulse: table {=u32}..{=u32} rpm; periods under {=u32} ticks ({=u32} rpm) rejected; lost after {=u32} ticks ({=u32} rpm); bounce under {=u32} %, agreement within {=u32} %; alarm on at margin <= {=f32} rpm, off above {=f32} rpm",
        RANGE_MIN_RPM,
        RANGE_MAX_RPM,
        pulse.min_period_ticks(),
        LIMIT_RPM,
        pulse.lost_period_ticks(),
        LOST_RPM,
        BOUNCE_PERCENT,
        MAX_CHANGE_PERCENT,
        alarm.on_margin_rpm,
        alarm.off_margin_rpm
    );
    defmt::info!("boot done: stack_peak_bytes={=u32}", stack_peak_bytes());

    let mut watchdog = IndependentWatchdog::new(dp.IWDG);
    watchdog.start(WATCHDOG_MS.millis());
    defmt::info!(
        "watchdog {=u32} ms; waiting for index pulses (alarm asserted: acquiring)",
        WATCHDOG_MS
    );

    let mut cause = Cause::Acquiring;
    let mut counts = Counts::default();
    let mut last_rpm = f32::NAN;
    let mut last_margin = f32::NAN;
    let mut last_status = capture.now();
    loop {
        watchdog.feed();
        let event = capture.poll();
        let reading = match event {
            Some(CaptureEvent::Edge(t)) => pulse.capture(t),
            Some(CaptureEvent::Overrun(t)) => {
                // An edge was lost: forget every pulse, the later one starts over.
                pulse.resync();
                pulse.capture(t)
            }
            None => {
                let now = capture.now();
                if now.wrapping_sub(last_status) >= STATUS_TICKS {
                    last_status = now;
                    defmt::info!(
                        "status rpm={=f32} speed_margin_rpm={=f32} alarm={=bool} cause={} counts={} stack_peak_bytes={=u32}",
                        last_rpm, last_margin, out.is_asserted(), cause, counts, stack_peak_bytes()
                    );
                }
                match pulse.poll(now) {
                    Some(r) => r,
                    None => continue,
                }
            }
        };

        let overrun = matches!(event, Some(CaptureEvent::Overrun(_)));
        let (margin, new_cause) = match reading {
            _ if overrun => (f32::NAN, Cause::CaptureOverrun),
            SpeedReading::Rpm(rpm) => {
                let p = predictor.predict(rpm);
                counts.vouched += 1;
                last_rpm = rpm;
                last_margin = p.speed_margin_rpm;
                defmt::debug!(
                    "rpm={=f32} speed_margin_rpm={=f32} force_margin_lb={=f32}",
                    rpm,
                    p.speed_margin_rpm,
                    p.force_margin_lb
                );
                (p.speed_margin_rpm, Cause::Margin)
            }
            SpeedReading::OutOfRange(rpm) => {
                counts.out_of_range += 1;
                last_rpm = rpm;
                last_margin = f32::NAN;
                if cause != Cause::OutOfRange {
                    defmt::warn!(
                        "speed {=f32} rpm outside the table's {=u32}..{=u32} rpm: not extrapolated",
                        rpm,
                        RANGE_MIN_RPM,
                        RANGE_MAX_RPM
                    );
                }
                (f32::NAN, Cause::OutOfRange)
            }
            SpeedReading::Rejected(r) => {
                counts.rejected += 1;
                match r {
                    Rejection::TooShort { period_ticks } => defmt::warn!(
                        "pulse rejected: {=u32} ticks since the last, faster than {=u32} rpm (noise or bounce)",
                        period_ticks,
                        LIMIT_RPM
                    ),
                    Rejection::Bounce { period_ticks } => defmt::warn!(
                        "pulse rejected: {=u32} ticks, under {=u32} % of the last period (bounce)",
                        period_ticks,
                        BOUNCE_PERCENT
                    ),
                    Rejection::Step { period_ticks } => defmt::warn!(
                        "period rejected: {=u32} ticks, more than {=u32} % off the last (missed pulse or step)",
                        period_ticks,
                        MAX_CHANGE_PERCENT
                    ),
                }
                (f32::NAN, Cause::Rejected)
            }
            SpeedReading::Lost => {
                counts.lost += 1;
                last_rpm = f32::NAN;
                last_margin = f32::NAN;
                defmt::warn!(
                    "speed lost: no index pulse for {=u32} ticks (a revolution at {=u32} rpm)",
                    pulse.lost_period_ticks(),
                    LOST_RPM
                );
                (f32::NAN, Cause::Lost)
            }
            SpeedReading::Acquiring => (f32::NAN, Cause::Acquiring),
        };
        if overrun {
            counts.overruns += 1;
            defmt::warn!("capture overrun: an index edge was lost; acquiring again");
        }
        cause = new_cause;

        let asserted = alarm.update(margin);
        // The HAL's GPIO writes cannot fail (Infallible).
        let Ok(changed) = out.set_asserted(asserted);
        if changed && asserted {
            defmt::warn!(
                "alarm ASSERTED (PA5 low): {} rpm={=f32} speed_margin_rpm={=f32}",
                cause,
                last_rpm,
                last_margin
            );
        } else if changed {
            defmt::info!(
                "alarm released (PA5 high): rpm={=f32} speed_margin_rpm={=f32} > {=f32}",
                last_rpm,
                last_margin,
                alarm.off_margin_rpm
            );
        }
    }
}

#[exception]
unsafe fn HardFault(ef: &ExceptionFrame) -> ! {
    drive_alarm_safe_from_fault();
    defmt::error!(
        "HardFault at pc={=u32:#010x}: alarm asserted (PA5 low); parked until the watchdog or a reset",
        ef.pc()
    );
    loop {
        cortex_m::asm::nop();
    }
}

#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    drive_alarm_safe_from_fault();
    defmt::error!(
        "unexpected interrupt {=i16}: alarm asserted (PA5 low); parked",
        irqn
    );
    loop {
        cortex_m::asm::nop();
    }
}
