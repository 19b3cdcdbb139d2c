//! The vendored real robot descriptions (`tests/data/robots/`, see its SOURCE.md): unpacked once
//! (gzip meshes inflated) into the build's temporary directory (the system's for examples).

use std::io::Read;
use std::path::{Path, PathBuf};

/// One arm of the vendored set.
#[derive(Clone, Copy, Debug)]
#[allow(dead_code)]
pub struct Arm {
    /// Short name.
    pub name: &'static str,
    /// URDF path under the package directory.
    pub urdf: &'static str,
    /// Tool link.
    pub tip: &'static str,
    /// Actuated joints on the path to the tool.
    pub dof: usize,
    /// Collision elements in the whole URDF (meshes and primitives).
    pub elements: usize,
}

/// The vendored arms.
#[allow(dead_code)]
pub const ARMS: [Arm; 7] = [
    Arm {
        name: "ur3",
        urdf: "robots/ur_description/urdf/ur3_robot.urdf",
        tip: "tool0",
        dof: 6,
        elements: 8,
    },
    Arm {
        name: "ur5",
        urdf: "robots/ur_description/urdf/ur5_robot.urdf",
        tip: "tool0",
        dof: 6,
        elements: 8,
    },
    Arm {
        name: "ur10",
        urdf: "robots/ur_description/urdf/ur10_robot.urdf",
        tip: "tool0",
        dof: 6,
        elements: 8,
    },
    Arm {
        name: "panda",
        urdf: "robots/panda_description/urdf/panda.urdf",
        tip: "panda_hand_tcp",
        dof: 7,
        elements: 17,
    },
    Arm {
        name: "xarm7",
        urdf: "robots/xarm_description/urdf/xarm7.urdf",
        tip: "link_eef",
        dof: 7,
        elements: 8,
    },
    Arm {
        name: "kinova",
        urdf: "robots/kinova_description/robots/kinova.urdf",
        tip: "j2s6s200_end_effector",
        dof: 6,
        elements: 11,
    },
    Arm {
        name: "baxter_right",
        urdf: "robots/baxter_description/urdf/baxter.urdf",
        tip: "right_gripper",
        dof: 7,
        elements: 41,
    },
];

fn copy_tree(src: &Path, dst: &Path) {
    std::fs::create_dir_all(dst).unwrap();
    for e in std::fs::read_dir(src).unwrap() {
        let e = e.unwrap();
        let p = e.path();
        let name = e.file_name().into_string().unwrap();
        if p.is_dir() {
            copy_tree(&p, &dst.join(&name));
        } else if let Some(stem) = name.strip_suffix(".gz") {
            let mut out = Vec::new();
            flate2::read::GzDecoder::new(std::fs::File::open(&p).unwrap())
                .read_to_end(&mut out)
                .unwrap();
            std::fs::write(dst.join(stem), out).unwrap();
        } else {
            std::fs::copy(&p, dst.join(&name)).unwrap();
        }
    }
}

/// The package directory holding `example-robot-data/` (pass it as `--package-path`).
#[allow(dead_code)]
pub fn package_dir() -> PathBuf {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        // Tests and benches get the build's temporary directory; examples the system's.
        let base = option_env!("CARGO_TARGET_TMPDIR").map_or_else(
            || std::env::temp_dir().join("helixreach-test-robots"),
            PathBuf::from,
        );
        let root = base.join("robots-v2");
        let done = root.join("example-robot-data/.unpacked");
        if !done.is_file() {
            let tmp = base.join(format!("robots-unpack-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&tmp);
            let src =
                Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/robots/example-robot-data");
            copy_tree(&src, &tmp.join("example-robot-data"));
            std::fs::write(tmp.join("example-robot-data/.unpacked"), "").unwrap();
            std::fs::create_dir_all(root.parent().unwrap()).unwrap();
            // Another test binary may have won the race: either copy is complete.
            if std::fs::rename(&tmp, &root).is_err() {
                let _ = std::fs::remove_dir_all(&tmp);
            }
        }
        assert!(
            done.is_file(),
            "unpacking the test robots failed: {}",
            root.display()
        );
        root
    })
    .clone()
}

/// The URDF path of an arm.
#[allow(dead_code)]
pub fn urdf(arm: &Arm) -> PathBuf {
    package_dir().join("example-robot-data").join(arm.urdf)
}

/// The model of an arm, meshes resolved through the package directory.
#[allow(dead_code)]
pub fn load(arm: &Arm) -> helixreach::robot::RobotModel {
    let opts = helixreach::robot::LoadOptions {
        search: helixreach::robot::mesh::MeshSearch {
            package_paths: vec![package_dir()],
            ros_package_path: false,
        },
        no_collision: Vec::new(),
    };
    helixreach::robot::RobotModel::from_urdf_file_with(urdf(arm), Some(arm.tip), &opts)
        .unwrap_or_else(|e| panic!("{}: {e}", arm.name))
}
