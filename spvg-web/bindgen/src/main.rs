//! `spvg-web-bindgen IN.wasm OUT_DIR`: the page's JS glue and its wasm, as
//! `wasm-bindgen --target web --no-typescript --remove-name-section
//! --remove-producers-section IN.wasm --out-dir OUT_DIR` writes them.
//!
//! The name section (function names for stack traces, about 140 kB) is not shipped: the
//! page's size budget is 200 kB gzipped.

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, out_dir] = args.as_slice() else {
        eprintln!("usage: spvg-web-bindgen IN.wasm OUT_DIR");
        return ExitCode::from(2);
    };
    let mut bindgen = wasm_bindgen_cli_support::Bindgen::new();
    bindgen
        .input_path(input)
        .typescript(false)
        .remove_name_section(true)
        .remove_producers_section(true)
        .omit_default_module_path(false);
    let result = bindgen.web(true).and_then(|b| b.generate(out_dir));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("spvg-web-bindgen: {error:#}");
            ExitCode::FAILURE
        }
    }
}
