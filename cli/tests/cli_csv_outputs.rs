//! Every table a command writes opens as written in pandas or a spreadsheet: each command that
//! writes CSV runs on a small input, and every `.csv` it wrote is read back by the `csv` crate
//! in strict mode (a header of distinct names, every record as long as it), with the header
//! each file documents; every Markdown table it wrote has as many cells in each row as in its
//! header. Class names holding a comma, a quote and a `|` travel through both intact.

mod common;
use common::{
    assert_markdown_tables_are_whole, files_with_extension, neurotac, read_csv_strict,
    recorded_classes, small_reproduce,
};
use std::path::Path;

/// The path as an argument.
fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Runs `neurotac ARGS`, failing with its error output.
fn run(args: &[&str]) {
    let (ok, _, stderr) = neurotac(args);
    assert!(ok, "neurotac {}: {stderr}", args.join(" "));
}

/// The header of `tradeoff simulator`'s `simulator.csv` (the study's simulator family shares
/// the file name, not the columns).
const SIMULATOR_TRADE_HEADER: &str = "tolerance,events_per_trial,signal_events_per_trial,count_error,mean_timing_error_us,median_timing_error_us,p95_timing_error_us,max_timing_error_us,spikes_per_taxel,pixel_steps_per_trial,trials_per_s,pareto";

/// The header a CSV file the commands write documents, by its file name; `None` for a
/// confusion matrix (its class names) or a table whose columns follow the codings.
fn documented_header(name: &str) -> Option<&'static str> {
    Some(match name {
        "accuracy.csv" => {
            "set,pipeline,coding,parameters,loo_accuracy,loo_std,wilson_low,wilson_high,split_accuracy,paper_accuracy,wall_s"
        }
        "parameters.csv" => "set,quantity,value,paper",
        "phase_shares.csv" => "set,class,press,onset,sliding,stop",
        "loo_recall.csv" => "set,class,intensive,spatial,temporal,spatiotemporal",
        "paper_confusions.csv" => "set,paper_statement,coding,measure,ours,paper",
        "accuracy_vs_time.csv" => "t_s,intensive,spatial,temporal,spatiotemporal",
        "neurons.csv" => {
            "model,integrator,precision,spike_times,dt_s,spikes,true_spikes,count_error,mean_time_error_s,max_time_error_s,updates_per_s,pareto"
        }
        n if n.starts_with("dt_sweep_") => "dt_ms,loo_accuracy",
        n if n.starts_with("bo_convergence_") => {
            "epoch,tau_s,cos,accuracy,best_accuracy,best_tau_s,best_cos"
        }
        _ => return None,
    })
}

#[test]
fn every_csv_and_markdown_table_the_commands_write_reads_back_whole() {
    let dir = tempfile::tempdir().unwrap();
    let (root, cache) = (dir.path(), dir.path().join("cache"));
    let classes = [r#"fine, "soft"|ribbed"#, "plain"].map(String::from);

    // reproduce, on a recorded set whose class names hold a comma, quotes and a `|` (the
    // slides are CSV event files, read by the same crate).
    let data = root.join("recorded");
    recorded_classes(&data, &[(classes[0].clone(), 4), (classes[1].clone(), 4)]);
    let report = root.join("report");
    run(&[
        "reproduce",
        "--dataset",
        s(&data),
        "--epochs",
        "8",
        "--tau-step",
        "30ms",
        "--out",
        s(&report),
    ]);
    // ... and on the artificial set (its phase shares and the paper's named confusions).
    let artificial = root.join("report-artificial");
    let (ok, _, stderr) = small_reproduce(&artificial, &cache, &[]);
    assert!(ok, "{stderr}");
    // tradeoff: the study (setting names with commas) and the two trades.
    let study = root.join("tradeoff");
    run(&[
        "tradeoff",
        "--quick",
        "--trials",
        "3",
        "--epochs",
        "10",
        "--cache",
        s(&cache),
        "--out",
        s(&study),
    ]);
    let trades = root.join("trades");
    run(&["tradeoff", "neurons", "--quick", "--out", s(&trades)]);
    run(&["tradeoff", "simulator", "--quick", "--out", s(&trades)]);
    // recognise --eval.
    let eval = root.join("eval");
    run(&[
        "recognise",
        "--eval",
        "--set",
        "artificial",
        "--trials",
        "5",
        "--cache",
        s(&cache),
        "--out",
        s(&eval),
    ]);
    // simulate's pixel events as CSV, without and with the source pin.
    let simulated = root.join("simulated");
    let labelled = root.join("labelled");
    for (out, extra) in [
        (&simulated, &["--event-format", "csv"][..]),
        (&labelled, &["--labels"][..]),
    ] {
        let mut args = vec![
            "simulate",
            "--set",
            "artificial",
            "--trials",
            "1",
            "--cache",
            s(&cache),
            "--out",
            s(out),
            "--pixel-events",
        ];
        args.extend_from_slice(extra);
        run(&args);
    }
    // convert and filter (and record, which writes through the same writer) to CSV.
    let events = root.join("events");
    std::fs::create_dir_all(&events).unwrap();
    let slide = data.join(&classes[0]).join("00.csv");
    run(&["convert", s(&slide), s(&events.join("converted.csv"))]);
    run(&["filter", s(&slide), s(&events.join("filtered.csv"))]);

    // Per folder, how many CSV files: a report's 5 tables, Δt sweep, optimisation trace and
    // 4 + 4 confusion matrices; a table per family of the study; one per trade; one of the
    // online evaluation; one per simulated slide (11 textures × 1); convert's and filter's.
    let expected = [
        (&report, 15),
        (&artificial, 15),
        (&study, 4),
        (&trades, 2),
        (&eval, 1),
        (&simulated, 11),
        (&labelled, 11),
        (&events, 2),
    ];
    for (folder, count) in expected {
        let files = files_with_extension(folder, "csv");
        assert_eq!(files.len(), count, "{}: {files:?}", folder.display());
        for path in files {
            let (header, rows) = read_csv_strict(&path);
            let name = path.file_name().unwrap().to_str().unwrap();
            let joined = header.join(",");
            if let Some(documented) = documented_header(name) {
                assert_eq!(joined, documented, "{}", path.display());
            } else if name.starts_with("confusion_") {
                let names: Vec<&str> = rows.iter().map(|r| r[0].as_str()).collect();
                assert_eq!(header[1..], names, "{}", path.display());
                if folder == &report {
                    assert_eq!(names, classes, "{}", path.display());
                }
            } else if folder == &study {
                let (head, tail) = ("setting,reference,wall_s,", ",front,recommended");
                assert!(
                    joined.starts_with(head) && joined.ends_with(tail),
                    "{}: {joined}",
                    path.display()
                );
            } else if folder == &trades {
                assert_eq!(joined, SIMULATOR_TRADE_HEADER, "{}", path.display());
            } else {
                let pin = folder == &labelled;
                let expected = if pin { "t,x,y,on,pin" } else { "t,x,y,on" };
                assert_eq!(joined, expected, "{}", path.display());
            }
        }
    }
    // The report's tables name the classes as they are.
    let (_, recall) = read_csv_strict(&report.join("loo_recall.csv"));
    let names: Vec<&str> = recall.iter().map(|r| r[1].as_str()).collect();
    assert_eq!(names, classes);
    // The study's setting names hold commas, each in one field.
    let (_, settings) = read_csv_strict(&study.join("artificial/transduction/transduction.csv"));
    assert_eq!(settings[0][0], "pool 20 ms, BA 5 ms");
    // Rows in the tables a recorded set leaves empty.
    for table in ["phase_shares.csv", "paper_confusions.csv"] {
        assert!(
            !read_csv_strict(&artificial.join(table)).1.is_empty(),
            "{table}"
        );
    }

    for folder in [&report, &artificial, &study, &trades, &eval] {
        for path in files_with_extension(folder, "md") {
            assert_markdown_tables_are_whole(&path);
        }
    }
}
