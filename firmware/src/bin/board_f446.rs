//! The cam-timing and jump predictor on a Nucleo-F446RE (STM32F446RE, Cortex-M4F at
//! 180 MHz): the same predictor as the QEMU image (the boot-time table of the chip's
//! scene, `camsim_firmware::workload::Predictor`), fed by a real index pulse.
//!
//! Boot: the alarm output is asserted (PA5 low, the safe state) before anything else;
//! the prediction table is built (tens of seconds); any failure stops here with the alarm
//! asserted. Then, forever: TIM2 capture on PA0 (`IndexCapture`, the board's
//! `camsim_core::CaptureTimer`) -> the chip's speed monitor ([`ChipMonitor`]: core's
//! `IndexPulse` -> a speed reading -> prediction -> `JumpAlarm` hysteresis) -> PA5, the
//! same monitor and trait the QEMU image feeds with its scripted pulse train; this binary
//! adds the HAL glue and the log. Only a vouched speed feeds its speed margin to the
//! alarm; every other reading (out of the table's range, rejected pulse, lost speed,
//! acquisition, capture overrun) asserts it, and it is released only once a vouched
//! margin exceeds the release threshold. The independent watchdog resets a stalled loop (pins reset = alarm);
//! a panic or fault drives PA5 low in the HardFault handler.
//!
//! Logs with defmt over RTT (`probe-rs run`, see `cargo board` in .cargo/config.toml).

#![no_std]
#![no_main]

use camsim_chip::{ChipMonitor, ChipStep};
use camsim_core::{CaptureTimer, SpeedReading};
use camsim_firmware::board::f446::{drive_alarm_safe_from_fault, IndexCapture, TICK_HZ};
use camsim_firmware::exit_failure;
use camsim_firmware::memory::{paint_stack, stack_peak_bytes, Sections};
use camsim_firmware::monitor::{
    error_name, log_alarm_change, log_config, log_fault, Counts, FailSafeOutput,
};
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
/// Independent watchdog timeout, ms (the loop feeds it every few microseconds).
const WATCHDOG_MS: u32 = 500;
/// A status line this often, capture ticks (10 s).
const STATUS_TICKS: u32 = 10 * TICK_HZ;
/// The alarm output's name in the log.
const ALARM_PIN: &str = "PA5";

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
    let reset = ResetCause::read_and_clear(&dp.RCC);

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
    log_board(rcc.clocks.sysclk().raw(), tick_hz, &reset);
    if tick_hz != TICK_HZ {
        fail("TIM2 does not tick at 1 MHz (clock configuration)")
    }

    let predictor = boot_predictor(&mut capture);
    let mut monitor = match ChipMonitor::<f32>::new(tick_hz) {
        Ok(m) => m,
        Err(e) => {
            defmt::error!("speed monitor configuration: {=str}", error_name(&e));
            fail("invalid speed monitor configuration")
        }
    };
    // The monitor starts with the alarm asserted, until a vouched margin releases it.
    log_config(&monitor);
    defmt::info!("boot done: stack_peak_bytes={=u32}", stack_peak_bytes());

    let mut watchdog = IndependentWatchdog::new(dp.IWDG);
    watchdog.start(WATCHDOG_MS.millis());
    defmt::info!(
        "watchdog {=u32} ms; waiting for index pulses (alarm asserted: acquiring)",
        WATCHDOG_MS
    );

    let mut last = LastReading::new(capture.now());
    loop {
        watchdog.feed();
        let Some(step) = monitor.step(&predictor.table, &mut capture) else {
            last.status_if_due(capture.now(), out.is_asserted());
            continue;
        };
        last.record(&monitor, &step);
        // The HAL's GPIO writes cannot fail (Infallible).
        let Ok(changed) = out.set_asserted(step.alarm);
        if changed {
            log_alarm_change(ALARM_PIN, &step);
        }
    }
}

/// Why the last reset happened (a watchdog reset means the loop had stalled).
struct ResetCause {
    watchdog: bool,
    pin: bool,
    power: bool,
}

impl ResetCause {
    /// Reads RCC's reset flags, then clears them (so the next boot reads its own).
    fn read_and_clear(rcc: &pac::RCC) -> Self {
        let csr = rcc.csr().read();
        let cause = ResetCause {
            watchdog: csr.wdgrstf().bit_is_set(),
            pin: csr.padrstf().bit_is_set(),
            power: csr.porrstf().bit_is_set(),
        };
        rcc.csr().modify(|_, w| w.rmvf().set_bit());
        cause
    }
}

/// The board's lines: clock, pins, the last reset's cause and the image's sizes.
fn log_board(sysclk_hz: u32, tick_hz: u32, reset: &ResetCause) {
    let sections = Sections::get();
    defmt::info!(
        "board=nucleo-f446re sysclk_hz={=u32} tick_hz={=u32} capture=PA0 (TIM2_CH1, falling edge) alarm=PA5 (LD2 lit: speed vouched, margin fine; dark: alarm asserted, the safe state)",
        sysclk_hz,
        tick_hz
    );
    defmt::info!(
        "reset watchdog={=bool} pin={=bool} power={=bool}; flash_bytes={=u32} ram_static_bytes={=u32}",
        reset.watchdog,
        reset.pin,
        reset.power,
        sections.flash_bytes(),
        sections.ram_static_bytes()
    );
}

/// Boot: the prediction table over the scene's speed grid (the alarm stays asserted),
/// logged row by row with the jump onset and the boot time; a failure stops here.
fn boot_predictor(capture: &mut IndexCapture) -> Predictor {
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
    predictor
}

/// What the status line repeats between readings: the last reading's kind, speed and
/// margin, the count of each kind, and when the last status line was logged (ticks).
struct LastReading {
    kind: &'static str,
    rpm: f32,
    margin: f32,
    counts: Counts,
    status_at: u32,
}

impl LastReading {
    /// Acquiring, nothing read yet, at tick `now`.
    fn new(now: u32) -> Self {
        LastReading {
            kind: "acquiring",
            rpm: f32::NAN,
            margin: f32::NAN,
            counts: Counts::default(),
            status_at: now,
        }
    }

    /// A status line when [`STATUS_TICKS`] have passed since the last one (`now`, ticks).
    fn status_if_due(&mut self, now: u32, alarm: bool) {
        if now.wrapping_sub(self.status_at) >= STATUS_TICKS {
            self.status_at = now;
            defmt::info!(
                "status rpm={=f32} speed_margin_rpm={=f32} alarm={=bool} last={=str} counts={} stack_peak_bytes={=u32}",
                self.rpm, self.margin, alarm, self.kind, self.counts, stack_peak_bytes()
            );
        }
    }

    /// Counts a step's reading and logs it: a prediction at debug level, any other
    /// reading as a fault (a steady speed outside the range once, not every revolution).
    fn record(&mut self, monitor: &ChipMonitor<f32>, step: &ChipStep<f32>) {
        self.counts.add(&step.reading);
        let kind = step.reading.kind();
        match (step.prediction, step.reading) {
            (Some(p), _) => {
                self.rpm = p.rpm;
                self.margin = p.speed_margin_rpm;
                defmt::debug!(
                    "rpm={=f32} speed_margin_rpm={=f32} force_margin_lb={=f32}",
                    p.rpm,
                    p.speed_margin_rpm,
                    p.force_margin_lb
                );
            }
            (None, r) => {
                self.margin = f32::NAN;
                self.rpm = match r {
                    SpeedReading::OutOfRange(rpm) => rpm,
                    SpeedReading::Lost => f32::NAN,
                    _ => self.rpm,
                };
                if !(kind == "out_of_range" && self.kind == kind) {
                    log_fault(monitor, &r);
                }
            }
        }
        self.kind = kind;
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
