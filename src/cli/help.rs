//! `ncsheet --help`: the commands in groups (workbook, NC, geometry), each with the first line
//! of its own help. clap lists subcommands in one block, so the top-level help's template is
//! written here from the subcommands clap knows.

use clap::builder::StyledStr;

/// The commands of each group, in the order they are listed. A command in no group is listed
/// under the last heading, so that none goes missing from the help.
pub const GROUPS: &[(&str, &[&str])] = &[
    ("Workbook commands", &["eval", "set", "export", "repl", "show", "info", "functions", "macros", "serve"]),
    ("NC commands", &["run", "nc", "post"]),
    ("Geometry commands", &["cam", "arcfit", "ballpath"]),
    ("Help", &["help"]),
];

/// `command` with its subcommands listed under the headings of [`GROUPS`] in its help.
pub fn grouped(command: clap::Command) -> clap::Command {
    // clap adds `help` when it builds the command: build it first so that it is listed too.
    let mut command = command;
    command.build();
    let template = template(&command);
    command.help_template(template)
}

/// clap's own template for a command with subcommands, with `{subcommands}` written out in
/// groups.
fn template(command: &clap::Command) -> StyledStr {
    let header = command.get_styles().get_header();
    let literal = command.get_styles().get_literal();
    let subcommands: Vec<&clap::Command> = command.get_subcommands().filter(|s| !s.is_hide_set()).collect();
    let width = subcommands.iter().map(|s| s.get_name().chars().count()).max().unwrap_or(0);
    let line = |s: &clap::Command| {
        let about = s.get_about().map(|a| a.to_string()).unwrap_or_default();
        let pad = " ".repeat(width - s.get_name().chars().count());
        format!("  {literal}{}{literal:#}{pad}  {about}\n", s.get_name())
    };
    let mut text = String::from("{before-help}{about-with-newline}\n{usage-heading} {usage}\n");
    for (k, (heading, names)) in GROUPS.iter().enumerate() {
        let last = k + 1 == GROUPS.len();
        let named = names.iter().filter_map(|name| subcommands.iter().find(|s| s.get_name() == *name));
        let strays = subcommands.iter().filter(|s| last && !in_a_group(s.get_name()));
        let listed: Vec<&&clap::Command> = named.chain(strays).collect();
        if listed.is_empty() {
            continue;
        }
        text.push_str(&format!("\n{header}{heading}:{header:#}\n"));
        for s in listed {
            text.push_str(&line(s));
        }
    }
    text.push_str(&format!("\n{header}Options:{header:#}\n{{options}}{{after-help}}"));
    StyledStr::from(text)
}

fn in_a_group(name: &str) -> bool {
    GROUPS.iter().any(|(_, names)| names.contains(&name))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn every_command_is_in_one_group() {
        let mut command = super::super::Cli::command();
        command.build();
        for s in command.get_subcommands() {
            let groups = GROUPS.iter().filter(|(_, names)| names.contains(&s.get_name())).count();
            assert_eq!(groups, 1, "{} is in {groups} groups", s.get_name());
        }
    }
}
