//! Every rule of the device choice on fake device lists (no GPU needed).

use super::*;
use crate::vk::DeviceKind;

/// A device with a compute queue; `uuid_byte` fills its UUID, `bus` its PCI bus number.
fn device(index: usize, name: &str, kind: DeviceKind, vendor_id: u32, uuid_byte: u8) -> DeviceInfo {
    DeviceInfo {
        index,
        name: name.into(),
        kind,
        api_version: "1.3.0".into(),
        compute_queue_family: Some(0),
        uuid: [uuid_byte; 16],
        vendor_id,
        pci_bus: None,
        ray_queries: false,
    }
}

fn nvidia(index: usize, name: &str, uuid_byte: u8, bus: Option<u32>) -> DeviceInfo {
    DeviceInfo {
        pci_bus: bus.map(|bus| PciBusInfo {
            domain: 0,
            bus,
            device: 0,
            function: 0,
        }),
        ..device(
            index,
            name,
            DeviceKind::DiscreteGpu,
            NVIDIA_VENDOR_ID,
            uuid_byte,
        )
    }
}

fn lavapipe(index: usize) -> DeviceInfo {
    device(
        index,
        "llvmpipe (LLVM 15.0.1, 256 bits)",
        DeviceKind::Cpu,
        0x10005,
        0x11,
    )
}

/// Two NVIDIA GPUs whose Vulkan order (0, 1) is the reverse of their PCI order, and lavapipe.
fn node() -> Vec<DeviceInfo> {
    vec![
        nvidia(0, "NVIDIA H100", 0xaa, Some(0x41)),
        nvidia(1, "NVIDIA A100", 0xbb, Some(0x01)),
        lavapipe(2),
    ]
}

fn env(cuda: Option<&str>) -> DeviceEnvironment {
    DeviceEnvironment {
        cuda_visible_devices: cuda.map(Into::into),
        ..DeviceEnvironment::default()
    }
}

fn uuid(byte: u8) -> String {
    format_uuid(&[byte; 16])
}

fn chosen(
    devices: &[DeviceInfo],
    device: Option<&str>,
    environment: &DeviceEnvironment,
) -> Vec<usize> {
    choose_devices(devices, device, environment, false)
        .unwrap_or_else(|e| panic!("{device:?} {environment:?}: {e}"))
        .indices
}

fn error(devices: &[DeviceInfo], device: Option<&str>, environment: &DeviceEnvironment) -> String {
    let message = choose_devices(devices, device, environment, false)
        .expect_err("no choice")
        .to_string();
    assert!(!message.contains('\n'), "one line: {message}");
    message
}

#[test]
fn uuids_are_formatted_as_nvidia_does() {
    let mut bytes = [0u8; 16];
    for (i, b) in bytes.iter_mut().enumerate() {
        *b = i as u8 * 17;
    }
    assert_eq!(
        format_uuid(&bytes),
        "GPU-00112233-4455-6677-8899-aabbccddeeff"
    );
}

#[test]
fn device_takes_an_index_a_name_a_uuid_or_a_unique_prefix() {
    let devices = node();
    assert_eq!(chosen(&devices, Some("1"), &env(None)), [1]);
    assert_eq!(chosen(&devices, Some("h100"), &env(None)), [0]);
    assert_eq!(chosen(&devices, Some(&uuid(0xbb)), &env(None)), [1]);
    assert_eq!(
        chosen(&devices, Some(&uuid(0xbb).to_uppercase()), &env(None)),
        [1]
    );
    assert_eq!(chosen(&devices, Some("GPU-aaaa"), &env(None)), [0]);
    // An index is an index, not a digit of a name ("LLVM 15.0.1" contains a 1).
    assert_eq!(chosen(&devices, Some("1"), &env(None)), [1]);
    // A number that is no index may still be part of a name ("LLVM 15.0.1"); one that is
    // part of two (H100, A100) names both (issue 58: it took the first).
    assert_eq!(chosen(&devices, Some("15"), &env(None)), [2]);
    let message = error(&devices, Some("100"), &env(None));
    assert!(message.contains("'100' matches 2 devices"), "{message}");
}

#[test]
fn an_unknown_uuid_is_one_line_naming_the_devices() {
    let message = error(&node(), Some("GPU-ffff"), &env(None));
    assert!(
        message.contains("no Vulkan device matches 'GPU-ffff'"),
        "{message}"
    );
    assert!(message.contains(&uuid(0xaa)), "{message}");
}

#[test]
fn a_name_that_matches_two_devices_names_both() {
    // Issue 58: two lavapipe ICDs (Mesa 22 and 25) took the first, silently.
    let devices = [
        lavapipe(0),
        lavapipe(1),
        nvidia(2, "NVIDIA H100", 0xaa, None),
    ];
    let message = error(&devices, Some("llvmpipe"), &env(None));
    assert!(
        message.contains("'llvmpipe' matches 2 devices"),
        "{message}"
    );
    assert!(
        message.contains("0 llvmpipe") && message.contains("1 llvmpipe"),
        "{message}"
    );
    assert_eq!(chosen(&devices, Some("h100"), &env(None)), [2]);
    // A whole name given exactly picks that device, even where it is part of another's.
    let devices = [
        device(0, "GPU X", DeviceKind::DiscreteGpu, 1, 1),
        device(1, "GPU X Pro", DeviceKind::DiscreteGpu, 1, 2),
    ];
    assert_eq!(chosen(&devices, Some("gpu x"), &env(None)), [0]);
}

#[test]
fn a_wrong_vkpath_device_is_named() {
    let environment = DeviceEnvironment {
        vkpath_device: Some("quadro".into()),
        ..DeviceEnvironment::default()
    };
    let message = error(&node(), None, &environment);
    assert!(
        message.starts_with("VKPATH_DEVICE=quadro: no Vulkan device matches 'quadro'"),
        "{message}"
    );
    // --device overrides it, and speaks for itself.
    let message = error(&node(), Some("quadro"), &environment);
    assert!(
        message.starts_with("no Vulkan device matches 'quadro'"),
        "{message}"
    );
}

#[test]
fn an_ambiguous_uuid_prefix_asks_for_more() {
    let devices = [nvidia(0, "A", 0xaa, None), nvidia(1, "B", 0xaa, None)];
    let message = error(&devices, Some("GPU-aa"), &env(None));
    assert!(message.contains("matches 2 devices"), "{message}");
}

#[test]
fn device_comes_before_vkpath_device_before_cuda_visible_devices() {
    let devices = node();
    let both = DeviceEnvironment {
        vkpath_device: Some(uuid(0xbb)),
        cuda_visible_devices: Some(uuid(0xaa)),
        ..DeviceEnvironment::default()
    };
    let choice = choose_devices(&devices, Some("2"), &both, false).unwrap();
    assert_eq!(choice.indices, [2]);
    assert!(choice.reason.starts_with("--device 2"), "{}", choice.reason);
    assert!(choice.reason.contains("not applied"), "{}", choice.reason);
    let choice = choose_devices(&devices, None, &both, false).unwrap();
    assert_eq!(choice.indices, [1]);
    assert!(
        choice.reason.starts_with("VKPATH_DEVICE=GPU-bbbb"),
        "{}",
        choice.reason
    );
    assert_eq!(chosen(&devices, None, &env(Some(&uuid(0xaa)))), [0]);
    // A CUDA list vkpath cannot map (indices without PCI order) does not stop --device.
    assert_eq!(chosen(&devices, Some("1"), &env(Some("1"))), [1]);
}

#[test]
fn without_any_the_best_ranked_device_is_taken() {
    let devices = vec![lavapipe(0), nvidia(1, "NVIDIA H100", 0xaa, None)];
    let choice = choose_devices(&devices, None, &env(None), false).unwrap();
    assert_eq!(choice.indices, [1]);
    assert!(choice.reason.starts_with("default"), "{}", choice.reason);
}

#[test]
fn cuda_uuid_entries_match_exactly_and_the_first_is_taken() {
    let devices = node();
    let listed = format!("{},{}", uuid(0xbb), uuid(0xaa));
    let choice = choose_devices(&devices, None, &env(Some(&listed)), false).unwrap();
    assert_eq!(choice.indices, [1]);
    assert_eq!(choice.reason, format!("CUDA_VISIBLE_DEVICES={listed}"));
    // --device all takes all of them, in the listed order.
    let choice = choose_devices(&devices, Some("all"), &env(Some(&listed)), false).unwrap();
    assert_eq!(choice.indices, [1, 0]);
    assert!(choice.several);
    // A prefix is not an exact UUID.
    let message = error(&devices, None, &env(Some("GPU-bbbb")));
    assert!(
        message.contains("CUDA_VISIBLE_DEVICES entry GPU-bbbb"),
        "{message}"
    );
}

#[test]
fn cuda_indices_need_pci_bus_order() {
    let devices = node();
    let message = error(&devices, None, &env(Some("0")));
    assert!(
        message.contains("CUDA_DEVICE_ORDER=PCI_BUS_ID"),
        "{message}"
    );
    assert!(message.contains("list UUIDs instead"), "{message}");
    let pci = |value: &str| DeviceEnvironment {
        cuda_visible_devices: Some(value.into()),
        cuda_device_order: Some("PCI_BUS_ID".into()),
        ..DeviceEnvironment::default()
    };
    // By PCI bus, the A100 (bus 0x01) is CUDA 0 and the H100 (bus 0x41) CUDA 1.
    assert_eq!(chosen(&devices, None, &pci("0")), [1]);
    assert_eq!(chosen(&devices, None, &pci("1")), [0]);
    assert_eq!(chosen(&devices, Some("all"), &pci("1,0")), [0, 1]);
    let message = error(&devices, None, &pci("2"));
    assert!(
        message.contains("CUDA index 2 is past the 2 NVIDIA device(s)"),
        "{message}"
    );
    // Without VK_EXT_pci_bus_info the order cannot be known.
    let no_bus = vec![nvidia(0, "A", 0xaa, None), nvidia(1, "B", 0xbb, None)];
    let message = error(&no_bus, None, &pci("0"));
    assert!(message.contains("VK_EXT_pci_bus_info"), "{message}");
}

#[test]
fn one_nvidia_device_is_cuda_index_zero_in_any_order() {
    let devices = vec![lavapipe(0), nvidia(1, "NVIDIA L4", 0xaa, None)];
    assert_eq!(chosen(&devices, None, &env(Some("0"))), [1]);
    assert!(error(&devices, None, &env(Some("1"))).contains("CUDA index 1 is past"));
}

#[test]
fn an_empty_or_minus_one_cuda_list_means_no_gpu() {
    let devices = node();
    for value in ["", "-1", "-1,0"] {
        let choice = choose_devices(&devices, None, &env(Some(value)), false).unwrap();
        assert_eq!(choice.indices, [2], "{value:?}");
        assert!(
            choice.reason.contains("gives this task no GPU"),
            "{}",
            choice.reason
        );
        let message = choose_devices(&devices, None, &env(Some(value)), true)
            .unwrap_err()
            .to_string();
        assert_eq!(
            message,
            format!("a GPU was required (--require-gpu), but CUDA_VISIBLE_DEVICES='{value}' gives this task no GPU")
        );
    }
    // CUDA's list ends at -1: "0,-1,1" is CUDA device 0 only (one NVIDIA device here).
    let one = vec![lavapipe(0), nvidia(1, "NVIDIA L4", 0xaa, None)];
    assert_eq!(chosen(&one, Some("all"), &env(Some("0,-1,1"))), [1]);
    let gpus_only = vec![nvidia(0, "NVIDIA L4", 0xaa, None)];
    assert!(error(&gpus_only, None, &env(Some("-1"))).contains("no CPU device"));
}

#[test]
fn cuda_visible_devices_is_ignored_without_nvidia_devices() {
    let devices = vec![lavapipe(0)];
    let choice = choose_devices(&devices, None, &env(Some(&uuid(0xaa))), true).unwrap();
    assert_eq!(choice.indices, [0]);
    assert!(
        choice.reason.contains("ignored: no NVIDIA device"),
        "{}",
        choice.reason
    );
    // An empty value (hiding CUDA GPUs) is not worth a word there.
    let choice = choose_devices(&devices, None, &env(Some("")), false).unwrap();
    assert!(!choice.reason.contains("CUDA"), "{}", choice.reason);
}

#[test]
fn mig_instances_and_garbage_entries_are_one_line_errors() {
    let devices = node();
    assert!(error(&devices, None, &env(Some("MIG-abcd"))).contains("MIG instance"));
    assert!(error(&devices, None, &env(Some("gpu0")))
        .contains("'gpu0' is neither a CUDA index nor a GPU- UUID"));
}

#[test]
fn devices_without_a_compute_queue_are_refused() {
    let mut graphics_only = nvidia(0, "graphics only", 0xaa, None);
    graphics_only.compute_queue_family = None;
    let devices = [graphics_only];
    for selector in [None, Some("0"), Some("all")] {
        let message = error(&devices, selector, &env(None));
        assert!(message.contains("compute queue"), "{message}");
    }
    assert!(error(&devices, None, &env(Some(&uuid(0xaa)))).contains("compute queue"));
}

#[test]
fn vkpath_device_takes_lists_and_all() {
    let devices = node();
    let list = DeviceEnvironment {
        vkpath_device: Some("2,0".into()),
        ..DeviceEnvironment::default()
    };
    let choice = choose_devices(&devices, None, &list, false).unwrap();
    assert_eq!((choice.indices, choice.several), (vec![2, 0], true));
    let all = DeviceEnvironment {
        vkpath_device: Some("all".into()),
        ..DeviceEnvironment::default()
    };
    assert_eq!(chosen(&devices, None, &all), [0, 1, 2]);
}
