//! The `nvector` command-line tool and HTTP service.

fn main() {
    println!("nvector");
}
