//! End-to-end tests of the `stabound` command line: one test binary for every subcommand,
//! faults (broken pipes, interrupts, bad paths) and a seeded fuzz of malformed arguments.

#[allow(dead_code)]
mod common;

mod amax_certify;
mod certified_device_sets;
mod certified_sets;
mod certified_table;
mod cli_amax;
mod cli_boundary;
mod cli_buzz;
mod cli_certify;
mod cli_check;
mod cli_completions;
mod cli_elements;
mod cli_recommend;
mod cli_scene;
mod cli_step;
mod cli_table;
mod element_list;
mod figure_formats;
mod figures_cli;
mod finite_sets;
mod layers;
mod passivity;
#[cfg(unix)]
mod progress;
mod readme;
mod robust_cli;
mod robust_fuzz;
mod robust_sets;
mod safety;
mod serve;
mod stiff;
mod streaming;
mod table_lookup;
mod time_limit;
mod vocabulary;
