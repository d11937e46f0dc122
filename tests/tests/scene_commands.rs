//! Every command takes a scene (issue 17): `modal SCENE`, `contact SCENE` and `predict
//! SCENE` read the same file as `run SCENE`.

use camsim::cli::{main_from, parse_from, Command};

fn scene(name: &str, edit: impl Fn(String) -> String) -> std::path::PathBuf {
    let text = camsim::scene::default_text().unwrap();
    let p = std::env::temp_dir().join(format!("camsim-scene-{name}-{}.toml", std::process::id()));
    std::fs::write(&p, edit(text)).unwrap();
    p
}

#[test]
fn contact_takes_the_scenes_pair() {
    let reference = scene("contact-ref", |t| t);
    let bigger = scene("contact-r045", |t| {
        t.replace("roller_radius_in = 0.375", "roller_radius_in = 0.45")
    });
    let report = |p: &std::path::Path| {
        let Command::Contact(a) =
            parse_from(["camsim", "contact", p.to_str().unwrap(), "--force", "50"])
                .unwrap()
                .command
        else {
            panic!()
        };
        let d = camsim::scene::load(p).unwrap().design;
        camsim::cmd::contact::compute_for(
            a.force,
            &d.hertz,
            d.geometry.roller_radius,
            d.geometry.base_radius,
        )
        .unwrap()
    };
    // The reference scene is the built-in reference pair.
    let r = report(&reference);
    assert_eq!(r, camsim::cmd::contact::compute(50.0).unwrap());
    // Hertz's line contact: the width goes as the square root of the effective radius
    // r1 r2 / (r1 + r2) at the same force, materials and length.
    let b = report(&bigger);
    assert_eq!(b.roller_radius_in.in_inch(), 0.45);
    let reff = |r1: f64, r2: f64| r1 * r2 / (r1 + r2);
    let expect = (reff(0.45, 1.5) / reff(0.375, 1.5)).sqrt();
    assert!(
        (b.contact_width_in.in_inch() / r.contact_width_in.in_inch() - expect).abs() < 1e-12,
        "{b:?}"
    );
    // The binary takes it (it refused the argument before).
    assert_eq!(
        main_from([
            "camsim",
            "contact",
            bigger.to_str().unwrap(),
            "--force",
            "50",
            "--json"
        ]),
        0
    );
    for p in [reference, bigger] {
        let _ = std::fs::remove_file(p);
    }
}

#[test]
fn modal_takes_the_scenes_masses_and_springs() {
    let reference = scene("modal-ref", |t| t);
    let stiff = scene("modal-krs", |t| {
        t.replace(
            "spring_modal_rate_lb_per_in = 100.0",
            "spring_modal_rate_lb_per_in = 400.0",
        )
    });
    let analyse = |p: &std::path::Path| {
        let d = camsim::scene::load(p).unwrap().design;
        camsim::cmd::modal::analyse_with(camsim::cmd::modal::parameters(&d)).unwrap()
    };
    assert_eq!(analyse(&reference), camsim::cmd::modal::analyse().unwrap());
    let s = analyse(&stiff);
    assert_eq!(s.parameters.k_rs.in_inch(), 400.0);
    // A stiffer return spring raises every translational frequency; the rotational
    // system does not see it.
    let r = analyse(&reference);
    for (a, b) in r.translational_hz.iter().zip(&s.translational_hz) {
        assert!(b > a, "{a} {b}");
    }
    assert_eq!(r.rotational_hz, s.rotational_hz);
    assert_eq!(
        main_from(["camsim", "modal", stiff.to_str().unwrap(), "--json"]),
        0
    );
    for p in [reference, stiff] {
        let _ = std::fs::remove_file(p);
    }
}

#[test]
fn predict_takes_the_scene_positionally_like_run() {
    let p = scene("predict", |t| t);
    let path = p.to_str().unwrap();
    let Command::Predict(a) = parse_from(["camsim", "predict", path]).unwrap().command else {
        panic!()
    };
    assert_eq!(a.scene_file.as_deref(), Some(p.as_path()));
    let Command::Predict(b) = parse_from(["camsim", "predict", "--scene", path])
        .unwrap()
        .command
    else {
        panic!()
    };
    assert_eq!(b.scene.as_deref(), Some(p.as_path()));
    // Both at once is a usage error.
    assert!(parse_from(["camsim", "predict", path, "--scene", path]).is_err());
    let _ = std::fs::remove_file(p);
}

/// A linker script with a 256 KiB flash and 64 KiB RAM budget in `dir`.
fn memory_x_in(dir: &std::path::Path) -> std::path::PathBuf {
    let memory_x = dir.join("memory.x");
    std::fs::write(
        &memory_x,
        "MEMORY\n{\n  FLASH : ORIGIN = 0x08000000, LENGTH = 256K\n  RAM : ORIGIN = 0x20000000, LENGTH = 64K\n}\n",
    )
    .unwrap();
    memory_x
}

#[test]
fn firmware_check_json_reports_the_budget_and_the_checks() {
    let d = std::env::temp_dir().join(format!("camsim-fwcheck-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let memory_x = memory_x_in(&d);
    let log = d.join("boot.log");
    std::fs::write(&log, "ERROR boot: table build failed: step budget exceeded\nERROR alarm asserted (LED0 low: true), stopped: boot failed\n").unwrap();
    let argv = [
        "camsim",
        "firmware-check",
        "--memory-x",
        memory_x.to_str().unwrap(),
        "--boot-fault",
        log.to_str().unwrap(),
        "--json",
    ];
    let Command::FirmwareCheck(a) = parse_from(argv).unwrap().command else {
        panic!("not firmware-check")
    };
    assert!(a.json);
    let r = camsim::cmd::firmware_check::report(&a).unwrap();
    assert_eq!(
        (r.flash_budget_bytes, r.ram_budget_bytes),
        (256 * 1024, 64 * 1024)
    );
    assert_eq!(r.checks.len(), 2, "{:?}", r.checks);
    assert!(
        r.checks[1].contains("boot failure reported"),
        "{:?}",
        r.checks
    );
    let v: serde_json::Value = serde_json::to_value(&r).unwrap();
    assert_eq!(v["flash_budget_bytes"], 262_144);
    assert_eq!(main_from(argv), 0);
    // A log that went on after the failed boot fails with --json too.
    std::fs::write(&log, "ERROR boot: table build failed: step budget exceeded\nERROR alarm asserted (LED0 low: true), stopped: boot failed\ntable rpm=800\n").unwrap();
    assert_eq!(main_from(argv), 1);
    std::fs::remove_dir_all(&d).unwrap();
}

/// `firmware-check --fits ... --json` gives each ELF's sections as numbers (not only inside the
/// check lines): a stand-in `llvm-size` prints known sections, and the report's sums are the
/// sums of those (its `Total` the sum of every section listed, as llvm-size prints it).
#[cfg(unix)]
#[test]
fn firmware_check_json_gives_each_images_sections_as_numbers() {
    use std::os::unix::fs::PermissionsExt;
    let d = std::env::temp_dir().join(format!("camsim-fwfits-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let memory_x = memory_x_in(&d);
    let tool = d.join("fake-llvm-size");
    std::fs::write(
        &tool,
        "#!/bin/sh\nprintf 'x  :\\nsection size addr\\n.vector_table 1024 0\\n.text 80000 1024\\n.rodata 8900 81024\\n.data 16 536870912\\n.bss 24 536870928\\n.uninit 8 536870952\\n.debug_info 99999 0\\nTotal 189971\\n'\n",
    )
    .unwrap();
    std::fs::set_permissions(&tool, std::fs::Permissions::from_mode(0o755)).unwrap();
    let elf = d.join("image.elf");
    std::fs::write(&elf, b"not read by the stand-in").unwrap();
    let argv = [
        "camsim",
        "firmware-check",
        "--memory-x",
        memory_x.to_str().unwrap(),
        "--llvm-size",
        tool.to_str().unwrap(),
        "--fits",
        elf.to_str().unwrap(),
        "--json",
    ];
    let Command::FirmwareCheck(a) = parse_from(argv).unwrap().command else {
        panic!("not firmware-check")
    };
    let r = camsim::cmd::firmware_check::report(&a).unwrap();
    let v: serde_json::Value = serde_json::to_value(&r).unwrap();
    let img = &v["images"][0];
    // flash = .vector_table + .text + .rodata + .data; static RAM = .data + .bss + .uninit.
    assert_eq!(img["flash_bytes"], 1024 + 80_000 + 8900 + 16);
    assert_eq!(img["ram_static_bytes"], 16 + 24 + 8);
    assert_eq!(img["text_bytes"], 80_000);
    assert_eq!(v["images"].as_array().unwrap().len(), 1);
    assert!(v["product"].is_null() && v["budget"].is_null());
    assert_eq!(main_from(argv), 0);
    std::fs::remove_dir_all(&d).unwrap();
}
