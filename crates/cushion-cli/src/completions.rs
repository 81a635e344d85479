//! `cushion completions SHELL`: the completion script of this command line for a shell, written
//! by clap_complete from the same clap definition the command parses with.

use clap::CommandFactory;
use clap_complete::Shell;

#[derive(clap::Args, Debug)]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell.
    pub shell: Shell,
}

pub fn run(args: CompletionsArgs) -> i32 {
    let mut cmd = super::Cli::command();
    clap_complete::generate(args.shell, &mut cmd, "cushion", &mut std::io::stdout());
    0
}
