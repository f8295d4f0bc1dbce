//! `spvg-web-bindgen IN.wasm OUT_DIR`: the page's JS glue and its wasm, as
//! `wasm-bindgen --target web --no-typescript --remove-name-section
//! --remove-producers-section IN.wasm --out-dir OUT_DIR` writes them.
//!
//! The name section (function names for stack traces, about 140 kB) is not shipped, and
//! the whole-line `//` comments of the WGSL sources that the wasm carries as text are
//! blanked to spaces (same length, so no offset moves; runs of spaces gzip to almost
//! nothing): the page's size budget is 200 kB gzipped.

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
    let result = bindgen
        .web(true)
        .and_then(|b| b.generate_output())
        .and_then(|mut out| {
            let data = &mut out.wasm_mut().data;
            let ids: Vec<_> = data.iter().map(|d| d.id()).collect();
            for id in ids {
                blank_line_comments(&mut data.get_mut(id).value);
            }
            out.emit(out_dir)
        });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("spvg-web-bindgen: {error:#}");
            ExitCode::FAILURE
        }
    }
}

/// Replaces every whole-line `//` comment in `bytes` (a line of spaces or tabs, then `//`,
/// up to its newline) by spaces, keeping every byte's offset. A comment without a newline
/// after it is left alone, and so is a `//` after code on its line (it could be inside a
/// string such as a URL).
fn blank_line_comments(bytes: &mut [u8]) {
    let mut line_start = true;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\n' => line_start = true,
            b' ' | b'\t' => {}
            b'/' if line_start && bytes.get(i + 1) == Some(&b'/') => {
                if let Some(len) = bytes[i..].iter().position(|&b| b == b'\n') {
                    bytes[i..i + len].fill(b' ');
                    i += len;
                    continue;
                }
                line_start = false;
            }
            _ => line_start = false,
        }
        i += 1;
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn only_whole_line_comments_become_spaces() {
        let mut text = b"a\n  // why\nlet x = 1; // kept\n// last\nhttps://x\n  //end".to_vec();
        let len = text.len();
        super::blank_line_comments(&mut text);
        assert_eq!(text.len(), len);
        assert_eq!(
            text,
            b"a\n        \nlet x = 1; // kept\n       \nhttps://x\n  //end".to_vec()
        );
    }
}
