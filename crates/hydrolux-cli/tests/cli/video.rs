//! Videos through ffmpeg: playable, whole or not at all, interruptions.

use super::*;

fn ffprobe(path: &std::path::Path, entries: &str) -> String {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-select_streams", "v:0", "-count_frames", "-show_entries"])
        .arg(format!("stream={entries}"))
        .args(["-of", "default=nw=1"])
        .arg(path)
        .output()
        .expect("ffprobe (CI installs ffmpeg)");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn videos_are_playable_and_written_whole_or_not_at_all() {
    let dir = scratch("video");
    let args = ["render", "--scene", "calm", "--width", "64", "--height", "36", "--frames", "5"];
    let with = |extra: &[&str]| -> Vec<String> {
        args.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let run = |a: &[String], env: &[(&str, Option<&str>)]| {
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        hydrolux_env(&a, &dir, env)
    };
    // H.264 in MP4 and VP9 in WebM, every frame, the size asked for.
    let (code, err) = run(&with(&["--out", "clip.mp4"]), &[]);
    assert_eq!(code, 0, "{err}");
    let probe = ffprobe(&dir.join("clip.mp4"), "codec_name,width,height,pix_fmt,nb_read_frames");
    for want in ["codec_name=h264", "width=64", "height=36", "pix_fmt=yuv420p", "nb_read_frames=5"]
    {
        assert!(probe.contains(want), "{want} in {probe}");
    }
    let (code, err) = run(&with(&["--out", "clip.webm", "--bitrate", "500k"]), &[]);
    assert_eq!(code, 0, "{err}");
    let probe = ffprobe(&dir.join("clip.webm"), "codec_name,nb_read_frames");
    assert!(probe.contains("codec_name=vp9") && probe.contains("nb_read_frames=5"), "{probe}");
    assert_eq!(files_in(&dir), ["clip.mp4", "clip.webm"]);

    // No ffmpeg: one line saying how to get it, nothing written.
    let empty = scratch("video-missing");
    for env in [
        vec![("HYDROLUX_FFMPEG", None), ("PATH", Some("/nonexistent"))],
        vec![("HYDROLUX_FFMPEG", Some("/nonexistent/ffmpeg"))],
    ] {
        let a: Vec<String> = with(&["--out", "none.mp4"]);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        let (code, err) = hydrolux_env(&a, &empty, &env);
        assert!(
            code == 1 && err.contains("ffmpeg") && err.contains("apt-get install ffmpeg"),
            "{err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(files_in(&empty).is_empty());
    }
    // ffmpeg failing mid-stream (it wrote part of its file, then quit).
    let script = dir.join("failing-ffmpeg.sh");
    std::fs::write(
        &script,
        "#!/bin/sh\nfor last; do :; done\necho partial > \"$last\"\nhead -c 20000 > /dev/null\n\
         echo 'Conversion failed!' >&2\nexit 1\n",
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    let failing = [("HYDROLUX_FFMPEG", Some(script.to_str().unwrap()))];
    let (code, err) = run(&with(&["--out", "broken.mp4"]), &failing);
    assert!(
        code == 1
            && err.contains("cannot write `broken.mp4`")
            && err.contains("Conversion failed!")
            && !err.contains("panicked"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(files_in(&dir), ["clip.mp4", "clip.webm", "failing-ffmpeg.sh"], "no partial file");

    // Sizes and options a video cannot take.
    for (extra, want) in [
        (vec!["--out", "x.png", "--crf", "20"], "--crf and --bitrate are for videos"),
        (vec!["--out", "x.mp4", "--crf", "60"], "0 (lossless) to 51"),
        (vec!["--out", "x.mp4", "--bitrate", "fast"], "--bitrate `fast`"),
        (vec!["--out", "x.mp4", "--crf", "20", "--bitrate", "8M"], "not both"),
        (vec!["--out", "x.gif"], "or .mp4 or .webm for a video"),
    ] {
        let (code, err) = run(&with(&extra), &[]);
        assert!(code == 1 && err.contains(want), "{extra:?}: {err}");
    }
    let odd = ["render", "--width", "63", "--height", "36", "--out", "odd.mp4"];
    let (code, err) = hydrolux(&odd, &dir);
    assert!(code == 1 && err.contains("63×36") && err.contains("even width and height"), "{err}");
    assert_eq!(files_in(&dir), ["clip.mp4", "clip.webm", "failing-ffmpeg.sh"]);
}

/// An ffmpeg that stops reading is stopped after the timeout and named;
/// one whose `#!` interpreter is missing is said so; SIGINT and SIGTERM
/// mid-video remove its temporary and end by the signal.
#[cfg(unix)]
#[test]
fn a_stuck_ffmpeg_and_interruptions_leave_nothing() {
    use std::os::unix::fs::PermissionsExt;
    use std::os::unix::process::ExitStatusExt;
    let dir = scratch("interrupt");
    let script = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).unwrap();
        p.to_str().unwrap().to_string()
    };
    let stuck = script("stuck.sh", "#!/bin/sh\nexec sleep 600\n");
    let lost = script("lost.sh", "#!/nonexistent/interpreter\n");
    let small = ["render", "--width", "64", "--height", "36", "--set", "whitewater.memory=1"];
    let args = |extra: &[&str]| -> Vec<String> {
        small.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    // 40 frames of 9 KB fill a pipe ffmpeg never reads.
    let a = args(&["--frames", "40", "--out", "v.mp4"]);
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    let env = [("HYDROLUX_FFMPEG", Some(stuck.as_str())), ("HYDROLUX_FFMPEG_TIMEOUT", Some("1"))];
    let (code, err) = hydrolux_env(&a, &dir, &env);
    assert!(code == 1 && err.contains("ffmpeg took no frame for 1 s, so it was stopped"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    let (code, err) = hydrolux_env(&a, &dir, &[("HYDROLUX_FFMPEG", Some(lost.as_str()))]);
    assert!(code == 1 && err.contains("interpreter `/nonexistent/interpreter`"), "{err}");
    assert_eq!(files_in(&dir), ["lost.sh", "stuck.sh"]);
    // Interrupted once its temporary video exists.
    for (signal, number) in [("INT", 2), ("TERM", 15)] {
        let a = args(&["--frames", "100000", "--out", "long.mp4"]);
        let child = Command::new(env!("CARGO_BIN_EXE_hydrolux"))
            .args(&a)
            .current_dir(&dir)
            .env("XDG_RUNTIME_DIR", std::env::temp_dir())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let started = std::time::Instant::now();
        while !files_in(&dir).iter().any(|f| f.ends_with(".tmp.mp4")) {
            assert!(started.elapsed().as_secs() < 120, "no temporary video appeared");
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
        std::thread::sleep(std::time::Duration::from_millis(500));
        let status = Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.signal(), Some(number), "SIG{signal}: {:?} {err}", out.status);
        assert!(err.contains(&format!("interrupted (SIG{signal})")), "{err}");
        assert_eq!(files_in(&dir), ["lost.sh", "stuck.sh"], "SIG{signal} left files");
    }
}
