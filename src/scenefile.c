/* scenefile.c - the scene file and the option files before PETSc reads them: -scene inserted (SceneInsertFile) once its
 * text, its keys and its YAML pass the checks (a line PETSc would misread or refuse with a traceback is named with
 * its line); YAML and plain option files parsed as PETSc would read them (YamlOptionsProblem, OptionFileProblem, for
 * main.c's checks of -options_file and the like); options given that nothing reads refused (SceneCheckUnused) or, for
 * PETSc's solvers read later, warned of (SceneWarnUnused). */
#include "scenefile.h"
#include "comm.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/types.h> /* ssize_t */
#include <yaml.h>

/* the next line of a scene file into *line (as getline, its line end kept): a line ends at LF, CR LF or a CR alone,
   all three YAML line breaks (old Mac files have CR alone: read by LF only, such a file was one line). -1 at the end,
   SCENE_LINE_NOMEM where the line does not fit in memory (not the end: what follows is unread) */
#define SCENE_LINE_NOMEM (-2)
static ssize_t SceneGetLine(char **line, size_t *cap, FILE *fp)
{
  size_t n = 0;
  int    c;

  while ((c = getc(fp)) != EOF) {
    if (n + 3 > *cap) {
      char *grown = realloc(*line, 2 * *cap + 128);
      if (!grown) return SCENE_LINE_NOMEM;
      *line = grown, *cap = 2 * *cap + 128;
    }
    (*line)[n++] = (char) c;
    if (c == '\n') break;
    if (c == '\r') {
      if ((c = getc(fp)) == '\n') (*line)[n++] = (char) c;
      else if (c != EOF) ungetc(c, fp);
      break;
    }
  }
  if (!n) return -1;
  (*line)[n] = 0;
  return (ssize_t) n;
}

/* a scene line past a UTF-8 byte order mark, on the file's first line (an editor's; the YAML parser skips it) */
static char *SkipBOM(char *line, int lineno)
{
  return lineno == 1 && !strncmp(line, "\xEF\xBB\xBF", 3) ? line + 3 : line;
}

/* a scene file with no option in it would run the default strip without a word: refuse it */

static PetscErrorCode CheckSceneHasOptions(MPI_Comm comm, const char *file)
{
  char  *line = NULL;
  size_t cap  = 0;
  int    found = 0, lineno = 0;
  ssize_t got = 0;
  FILE  *fp    = fopen(file, "r");
  unsigned char bom[2] = {0, 0};

  PetscFunctionBeginUser;
  PetscCheck(fp, comm, PETSC_ERR_FILE_OPEN, "-scene %s: no such file, or not readable", file);
  if (fread(bom, 1, 2, fp) == 2 && ((bom[0] == 0xFF && bom[1] == 0xFE) || (bom[0] == 0xFE && bom[1] == 0xFF))) {
    fclose(fp); /* UTF-16: "holds no option", which did not say why */
    SETERRQ(comm, PETSC_ERR_USER_INPUT, "-scene %s: a UTF-16 file (its first bytes are UTF-16's byte-order mark); save it as UTF-8", file);
  }
  rewind(fp);
  while (!found && (got = SceneGetLine(&line, &cap, fp)) >= 0) { /* whole lines, of any length */
    const char *c = SkipBOM(line, ++lineno);
    while (*c == ' ' || *c == '\t') c++;
    if (*c && *c != '#' && *c != '\n' && *c != '\r' && strchr(c, ':')) found = 1;
  }
  free(line);
  fclose(fp);
  PetscCheck(got != SCENE_LINE_NOMEM, comm, PETSC_ERR_MEM, "-scene %s: line %d does not fit in memory", file, lineno + 1);
  PetscCheck(found, comm, PETSC_ERR_USER_INPUT,
             "-scene %s: the file holds no option (an empty scene would run the default strip)", file);
  PetscFunctionReturn(0);
}

/* a line of a scene file, its line end cut: where its key starts, or NULL where it has none
   (blank, a comment, a list item, a flow or quoted start) */
static char *KeyLine(char *line)
{
  char *c = line;
  line[strcspn(line, "\r\n")] = 0;
  while (*c == ' ' || *c == '\t') c++;
  return !*c || *c == '#' || *c == '-' || *c == '[' || *c == '{' || *c == '"' || *c == '\'' ? NULL : c;
}

/* What libyaml (PETSc's YAML reader) finds wrong with the text, and where: "line L, column C:
   problem (context)"; 0 if it parses. PETSc says only "YAML parser loading error". */
static int YamlProblem(const char *text, char *msg, size_t len)
{
  yaml_parser_t p;
  yaml_event_t  e;
  int           bad = 0, done = 0;

  if (!yaml_parser_initialize(&p)) return 0;
  yaml_parser_set_input_string(&p, (const unsigned char *) text, strlen(text));
  while (!done && !bad) {
    if (!yaml_parser_parse(&p, &e)) bad = 1;
    else {
      done = e.type == YAML_STREAM_END_EVENT;
      yaml_event_delete(&e);
    }
  }
  if (bad && p.error == YAML_READER_ERROR) { /* a byte that is not UTF-8: libyaml gives its offset, no mark; of a
                                                  bad trailing byte, the sequence's leading one is named */
    unsigned long line = 1, col = 1;
    size_t        lead = p.problem_offset;
    if (p.problem && strstr(p.problem, "trailing")) { /* back over the sequence's continuation bytes to its lead */
      while (lead > 0 && p.problem_offset - lead < 3 && ((unsigned char) text[lead - 1] & 0xC0) == 0x80) lead--;
      if (lead > 0 && (unsigned char) text[lead - 1] >= 0xC0) lead--;
    }
    for (size_t k = 0; k < lead && text[k]; k++) line += text[k] == '\n', col = text[k] == '\n' ? 1 : col + 1;
    snprintf(msg, len, "line %lu, column %lu: %s (byte 0x%02x; the file must be UTF-8)", line, col,
             p.problem ? p.problem : "a byte that cannot be read", (unsigned) (unsigned char) text[lead]);
  } else if (bad)
    snprintf(msg, len, "line %lu, column %lu: %s%s%s%s", (unsigned long) p.problem_mark.line + 1,
             (unsigned long) p.problem_mark.column + 1, p.problem ? p.problem : "a YAML error",
             p.context ? " (" : "", p.context ? p.context : "", p.context ? ")" : "");
  yaml_parser_delete(&p);
  return bad;
}

/* What PETSc's YAML option reader (PetscOptionsInsertStringYAML) would refuse in text, said as YamlProblem says it,
   or that a document is not a mapping of options ("key: value" lines) or has a key that is not a plain name; 0 if
   neither. Plain C: main.c asks it before PetscInitialize reads -options_file_yaml and PETSC_OPTIONS_YAML (whose
   refusal there is a traceback and an abort). */
typedef struct { /* a key's value on the line under the key, with key lines after it within its block */
  int  line;     /* 0: none */
  int  key_line; /* the first of those key lines */
  char text[104];
} Suspect;
static int FindBadKeyIn(FILE *fp, int options_only, char *msg, size_t len, Suspect *suspect);

typedef struct { /* a list of option names and values, as a command line lists them (OptionFileFree) */
  char **v;
  int    n, cap, failed; /* failed: out of memory, the list is incomplete */
} OptionList;

static void ListAdd(OptionList *l, const char *t)
{
  if (l->failed) return;
  if (l->n == l->cap) {
    char **v = realloc(l->v, (size_t) (2 * l->cap + 16) * sizeof *v);
    if (!v) {
      l->failed = 1;
      return;
    }
    l->v = v, l->cap = 2 * l->cap + 16;
  }
  if (!(l->v[l->n] = strdup(t))) l->failed = 1;
  else l->n++;
}

/* the list to the caller (opts not NULL and nothing refused, bad 0) or freed */
static void ListHand(OptionList *l, int bad, char ***opts, int *nopts)
{
  if (bad || l->failed || !opts) OptionFileFree(l->v, l->n); /* out of memory: its options are not looked at */
  else *opts = l->v, *nopts = l->n;
}

/* The options PETSc's YAML reader (PetscParseLayerYAML) sets from a mapping node: "-prefix" "key" for a scalar,
   the items of a sequence joined by commas (of a one-pair mapping item, its key, and the item under the prefix
   "key_"; a "$$" item skipped), a mapping under the prefix "key_"; "$$name: !include F" reads F (here
   -options_file_yaml F, then "-$$prefix" P if under the prefix P, which PETSc reads F's options under). A merge key
   "<<" is refused before (FindBadKeyIn), as keys PETSc cannot take. */
static void YamlFlatten(yaml_document_t *doc, yaml_node_t *node, const char *prefix, OptionList *l, int depth)
{
  if (!node || node->type != YAML_MAPPING_NODE || depth > 64) return;
  for (yaml_node_pair_t *q = node->data.mapping.pairs.start; q < node->data.mapping.pairs.top && !l->failed; q++) {
    yaml_node_t *k = yaml_document_get_node(doc, q->key), *v = yaml_document_get_node(doc, q->value);
    const char  *key;
    char         name[4096];
    if (!k || !v || k->type != YAML_SCALAR_NODE) continue;
    key = (const char *) k->data.scalar.value;
    if (!strncmp(key, "$$", 2)) {
      const char *tag = (const char *) v->tag;
      size_t      tl  = tag ? strlen(tag) : 0;
      if (v->type == YAML_SCALAR_NODE && tl >= 8 && !strcmp(tag + tl - 8, "!include")) {
        ListAdd(l, "-options_file_yaml"), ListAdd(l, (const char *) v->data.scalar.value);
        if (prefix[0]) ListAdd(l, "-$$prefix"), ListAdd(l, prefix); /* PETSc reads F's options under it */
      }
      continue;
    }
    snprintf(name, sizeof name, "%s%s", prefix, key);
    if (!strcasecmp(name, "options_file") || !strcasecmp(name, "options_file_yaml"))
      continue; /* PETSc does not read a file named by a YAML key, options: {file: F} neither (SceneCheckUnused says so) */
    if (v->type == YAML_SCALAR_NODE) {
      char opt[4100];
      snprintf(opt, sizeof opt, "-%s", name);
      ListAdd(l, opt), ListAdd(l, (const char *) v->data.scalar.value);
    } else if (v->type == YAML_MAPPING_NODE) {
      char sub[4100];
      snprintf(sub, sizeof sub, "%s_", name);
      YamlFlatten(doc, v, sub, l, depth + 1);
    } else if (v->type == YAML_SEQUENCE_NODE) { /* the scalar items joined (what -history etc. would get) */
      char opt[4100], joined[8192] = "";
      for (yaml_node_item_t *i = v->data.sequence.items.start; i < v->data.sequence.items.top; i++) {
        yaml_node_t *it = yaml_document_get_node(doc, *i);
        if (it && it->type == YAML_SCALAR_NODE && it->data.scalar.length) {
          size_t len = strlen(joined);
          snprintf(joined + len, sizeof joined - len, "%s%s", len ? "," : "", (const char *) it->data.scalar.value);
        } else if (it && it->type == YAML_MAPPING_NODE && it->data.mapping.pairs.top > it->data.mapping.pairs.start) {
          yaml_node_t *ik = yaml_document_get_node(doc, it->data.mapping.pairs.start->key); /* PETSc: one pair */
          char         sub[4100];
          size_t       len = strlen(joined);
          if (!ik || ik->type != YAML_SCALAR_NODE || !strncmp((const char *) ik->data.scalar.value, "$$", 2)) continue;
          snprintf(joined + len, sizeof joined - len, "%s%s", len ? "," : "", (const char *) ik->data.scalar.value);
          snprintf(sub, sizeof sub, "%s_", name);
          YamlFlatten(doc, it, sub, l, depth + 1);
        }
      }
      snprintf(opt, sizeof opt, "-%s", name);
      ListAdd(l, opt), ListAdd(l, joined);
    }
  }
}

int YamlOptionsProblem(const char *text, char *msg, size_t len, char ***opts, int *nopts)
{
  yaml_parser_t   p;
  yaml_document_t doc;
  int             bad = 0, done = 0;
  OptionList      list = {0};

  if (opts) *opts = NULL, *nopts = 0;
  if (YamlProblem(text, msg, len)) return 1;
  if (!yaml_parser_initialize(&p)) return 0;
  yaml_parser_set_input_string(&p, (const unsigned char *) text, strlen(text));
  while (!done && !bad) {
    yaml_node_t *root;
    if (!yaml_parser_load(&p, &doc)) break; /* YamlProblem found nothing: PETSc's own reader decides */
    root = yaml_document_get_root_node(&doc);
    done = root == NULL; /* the end of the stream */
    if (root && !(root->type == YAML_SCALAR_NODE && root->data.scalar.length == 0)) {
      if (root->type != YAML_MAPPING_NODE) {
        bad = 1;
        snprintf(msg, len, "line %lu: not a mapping of options ('key: value' lines)",
                 (unsigned long) root->start_mark.line + 1);
      } else {
        for (yaml_node_pair_t *q = root->data.mapping.pairs.start; q < root->data.mapping.pairs.top && !bad; q++) {
          yaml_node_t *key = yaml_document_get_node(&doc, q->key);
          if (key && key->type == YAML_SCALAR_NODE) continue;
          bad = 1;
          snprintf(msg, len, "line %lu: a key that is not a plain option name",
                   (unsigned long) (key ? key->start_mark.line : root->start_mark.line) + 1);
        }
        if (!bad && opts) YamlFlatten(&doc, root, "", &list, 0);
      }
    }
    yaml_document_delete(&doc);
  }
  yaml_parser_delete(&p);
  if (!bad && text[0]) { /* a key given twice: PETSc keeps the last, silently (as in a scene file) */
    FILE *fp = fmemopen((void *) text, strlen(text), "r");
    if (fp) {
      bad = FindBadKeyIn(fp, 1, msg, len, NULL) ? 1 : 0;
      fclose(fp);
    }
  }
  ListHand(&list, bad, opts, nopts);
  return bad;
}

/* PETSc's PetscOptionsValidKey: "-name" or "--name", a letter first, and not a number ("-1", "-inf") */
static int OptionKey(const char *t)
{
  char *end;
  if (t[0] != '-') return 0;
  if (t[1] == '-') t++;
  if (!isalpha((unsigned char) t[1])) return 0;
  (void) strtod(t, &end);
  return end == t || *end == '_' || isalnum((unsigned char) *end);
}

/* PETSc's PetscTokenFind on a line whose separators are spaces: a token ends at a space, and the
   spaces after it are skipped; one that starts with '"' ends at the next '"' and loses both; a line
   that starts with a space gives an empty first token. NULL at the end. */
static char *LineToken(char **at)
{
  char *p = *at, *t = p, stop = ' ';
  if (!p || !*p) return NULL;
  if (*p == '"') stop = '"', t = ++p;
  for (;; p++) {
    if (*p == stop) {
      *p++ = 0;
      while (*p == ' ') p++;
      *at = p;
      return t;
    }
    if (!*p) {
      *at = NULL;
      return t;
    }
  }
}

/* What PETSc's reader of an option file (PetscOptionsInsertFilePetsc) would refuse in text, with its line; 0 if
   nothing. Its rules: '#' starts a comment, tabs and carriage returns are spaces, tokens as LineToken finds them
   (an empty first one is passed over once), and a line holds "-option [value]" or "alias -new -old". Plain C:
   main.c asks it before PetscInitialize reads -options_file (whose refusal there is a traceback).
   opts (if not NULL): where nothing is refused, the file's options and their values in order, as a
   command line lists them (calloc'd, each string too: OptionFileFree), in *nopts. */
int OptionFileProblem(const char *text, char *msg, size_t len, char ***opts, int *nopts)
{
  char  *copy = strdup(text), *next = copy;
  size_t line = 1;
  int        bad  = 0;
  OptionList list = {0};

  if (opts) *opts = NULL, *nopts = 0;
  if (!copy) return 0;
  for (; next && *next && !bad; line++) {
    char *s = next, *at, *tok[4];
    next    = strchr(s, '\n');
    if (next) *next++ = 0;
    s[strcspn(s, "#")] = 0;
    for (char *q = s; *q; q++)
      if (*q == '\t' || *q == '\r') *q = ' ';
    at     = s;
    tok[0] = LineToken(&at);
    if (tok[0] && !tok[0][0]) tok[0] = LineToken(&at);
    for (int k = 1; k < 4; k++) tok[k] = LineToken(&at);
    if (!tok[0]) continue;
    bad = 1;
    if (tok[0][0] == '-') {
      if (!OptionKey(tok[0])) snprintf(msg, len, "line %zu: \"%s\" is no option name", line, tok[0]);
      else if (tok[1] && OptionKey(tok[1])) snprintf(msg, len, "line %zu: two options on one line (%s %s)", line, tok[0], tok[1]);
      else if (tok[2]) snprintf(msg, len, "line %zu: an extra value %s after %s %s (one value an option)", line, tok[2], tok[0], tok[1]);
      else {
        bad = 0;
        for (int k = 0; k < 2 && opts && tok[k]; k++) ListAdd(&list, tok[k]);
      }
    } else if (!strcasecmp(tok[0], "alias")) {
      if (!tok[1] || !OptionKey(tok[1]) || !tok[2] || !OptionKey(tok[2]))
        snprintf(msg, len, "line %zu: alias needs two option names (alias -new -old)", line);
      else if (tok[3]) snprintf(msg, len, "line %zu: %s after alias %s %s", line, tok[3], tok[1], tok[2]);
      else bad = 0;
    } else
      snprintf(msg, len, "line %zu: \"%s\" is no option (an option starts with '-'%s)", line, tok[0],
               strchr(tok[0], ':') ? "; key: value lines are YAML: name the file .yaml, or give it to -scene" : "");
  }
  free(copy);
  ListHand(&list, bad, opts, nopts);
  return bad;
}

void OptionFileFree(char **opts, int n)
{
  for (int k = 0; k < n; k++) free(opts[k]);
  free(opts);
}

/* The first line of a scene file that cannot be a YAML "key: value" line (no colon, or no space
   after the first one), as a hint when the YAML parser refuses the file without saying where.
   0 if none is found. */
static int FindMalformedLine(const char *file, char *text, size_t len, const char **why)
{
  char  *line = NULL;
  size_t cap  = 0;
  int    lineno = 0, found = 0;
  FILE  *fp = fopen(file, "r");

  if (!fp) return 0;
  while (!found && SceneGetLine(&line, &cap, fp) >= 0) {
    char *c, *colon, *start = SkipBOM(line, ++lineno);
    int   tab = memchr(start, '\t', strspn(start, " \t")) != NULL; /* libyaml refuses it, saying nowhere where */
    if (!(c = KeyLine(start))) continue;
    colon = strchr(c, ':');
    found = tab || !colon || (colon[1] && colon[1] != ' ' && colon[1] != '\t');
    *why  = tab ? "a tab in its indentation: YAML indents with spaces only" : "expected 'key: value'";
    if (found) snprintf(text, len, "%.100s", c); /* enough to recognise the line */
  }
  free(line);
  fclose(fp);
  return found ? lineno : 0;
}

/* the key at c, plain or quoted, into key; returns what follows its colon, or NULL if c holds
   no "key:" */
static char *SceneKey(char *c, char *key, size_t len)
{
  char  *colon;
  size_t klen;
  if (*c == '"' || *c == '\'') { /* a quoted key: PETSc's reader takes it as the plain one */
    char *end = strchr(c + 1, *c);
    if (!end) return NULL;
    for (colon = end + 1; *colon == ' ' || *colon == '\t'; colon++) {}
    if (*colon != ':') return NULL;
    snprintf(key, len, "%.*s", (int) PetscMin((size_t) (end - c - 1), (size_t) 100), c + 1);
    return colon + 1;
  }
  if (!(colon = strchr(c, ':'))) return NULL;
  klen = (size_t) (colon - c);
  while (klen && (c[klen - 1] == ' ' || c[klen - 1] == '\t')) klen--;
  snprintf(key, len, "%.*s", (int) PetscMin(klen, (size_t) 100), c);
  return colon + 1;
}

/* A key given twice in a scene file (PETSc's YAML reader keeps the last, silently), a 'scene'
   key in one (a scene does not include another), or what would hide keys from this check: a merge
   key '<<', an alias of a map, a flow map over lines, nested or at a line's start. The option, its
   line and the earlier one. Keys are flattened as PETSc does, a nested map's key joined to its
   parent's by '_' (a quoted key, and each key of a one-line flow map, too; an anchor or a tag
   before a value is passed over). 0 if none. */
#define SCENE_KEYS_MAX    512
#define SCENE_ANCHORS_MAX 64
typedef struct {
  char seen[SCENE_KEYS_MAX][128];
  int  at[SCENE_KEYS_MAX], nseen;
  int  options_only; /* a YAML option file, not a scene: a 'scene' key is the option's business, not this check's */
  char maps[SCENE_ANCHORS_MAX][64]; /* the anchors of maps: an alias of one hides its keys */
  int  nmaps;
} SceneKeys;

static int SceneKeyOnce(SceneKeys *k, const char *full, const char *value, int lineno, char *msg, size_t len)
{
  if (!k->options_only && !strcasecmp(full, "scene")) {
    snprintf(msg, len, "line %d: 'scene: %.100s': a scene file cannot name another scene", lineno, value);
    return lineno;
  }
  for (int q = 0; q < k->nseen; q++)
    if (!strcasecmp(k->seen[q], full)) { /* PETSc's option names ignore case */
      snprintf(msg, len, "line %d: -%.100s given twice (first at line %d); give it once", lineno, full, k->at[q]);
      return lineno;
    }
  if (k->nseen < SCENE_KEYS_MAX) snprintf(k->seen[k->nseen], sizeof k->seen[0], "%.120s", full), k->at[k->nseen++] = lineno;
  return 0;
}

/* v past an anchor (&name, whose name goes to anchor) and a tag (!tag) and the blanks after them */
static char *SceneValue(char *v, char *anchor, size_t len)
{
  anchor[0] = 0;
  while (*v == '&' || *v == '!') {
    const size_t n = strcspn(v, " \t");
    if (*v == '&') snprintf(anchor, len, "%.*s", (int) PetscMin(n - 1, (size_t) 60), v + 1);
    for (v += n; *v == ' ' || *v == '\t'; v++) {}
  }
  return v;
}

/* a merge key, or an alias of a map, as the value v of key at lineno: 0 if neither */
static int SceneHidden(const SceneKeys *k, const char *key, const char *v, int lineno, char *msg, size_t len)
{
  if (!strcmp(key, "<<")) {
    snprintf(msg, len, "line %d: a merge key '<<': write the keys it would merge", lineno);
    return lineno;
  }
  if (*v == '*')
    for (int q = 0; q < k->nmaps; q++) {
      const size_t n = strlen(k->maps[q]);
      if (!strncmp(v + 1, k->maps[q], n) && strchr(" \t,}#", v[1 + n])) {
        snprintf(msg, len, "line %d: '%.60s' stands for a map: write its keys", lineno, v);
        return lineno;
      }
    }
  return 0;
}

/* the one-line flow map v ("{...}", quotes respected) under the flattened key full: each item's key */
static int SceneFlowMap(SceneKeys *k, const char *full, char *v, int lineno, char *msg, size_t len)
{
  char *item = v + 1, *c = v + 1, q = 0;
  int   closed = 0;

  for (; *c && !closed; c++) {
    if (q) {
      if (q == '"' && *c == '\\' && c[1]) c++;
      else if (*c == q) q = 0;
      continue;
    }
    if (*c == '"' || *c == '\'') q = *c;
    else if (*c == '{' || *c == '[') break; /* a map or list in it */
    else if (*c == ',' || *c == '}') {
      char buf[512], sub[128], subfull[256], *iv;
      closed = *c == '}';
      snprintf(buf, sizeof buf, "%.*s", (int) PetscMin((size_t) (c - item), sizeof buf - 1), item);
      item = c + 1;
      for (iv = buf; *iv == ' ' || *iv == '\t'; iv++) {}
      if (!*iv || !(iv = SceneKey(iv, sub, sizeof sub))) continue;
      for (; *iv == ' ' || *iv == '\t'; iv++) {}
      if (SceneHidden(k, sub, iv, lineno, msg, len)) return lineno;
      snprintf(subfull, sizeof subfull, "%.120s_%.100s", full, sub);
      if (SceneKeyOnce(k, subfull, iv, lineno, msg, len)) return lineno;
    }
  }
  if (!closed) {
    snprintf(msg, len,
             "line %d: '%.60s': a flow map over several lines or with a map or list in it; write its keys on lines "
             "of their own",
             lineno, v);
    return lineno;
  }
  return 0;
}

/* the key of level depth - 1 (first at line at), flattened, whose value is not a map: value, on the lines under it,
   or "" (nothing under it: PETSc reads the option given with no value, a flag's true). Once, as any other key. */
static int SceneLevelKey(SceneKeys *k, char parent[][128], int depth, int at, const char *value, char *msg, size_t len)
{
  char full[128] = "";
  for (int d = 0; d < depth; d++) snprintf(full + strlen(full), sizeof full - strlen(full), "%s%.100s", d ? "_" : "", parent[d]);
  return SceneKeyOnce(k, full, value, at, msg, len);
}

/* *suspect (if given): the first key's value on the line under the key, when key lines follow that value within its
   block: YAML reads such lines as the value's continuation, or refuses the file ("tex 20" typed for "tex: 20" under
   "warp:"), where this line-by-line check took them for keys of the level above; its finding is then libyaml's to
   confirm, and that line the one to name if libyaml refuses (SceneInsertFile) */
static int FindBadKeyIn(FILE *fp, int options_only, char *msg, size_t len, Suspect *suspect)
{
  static SceneKeys keys;
  char            *line = NULL, parent[8][128];
  size_t           cap  = 0;
  int              indent[8], kids[8], at[8], anchored[8], depth = 0, lineno = 0, bad = 0;
  int              scalar_ind = -1, scalar_at = 0; /* a key's value on the lines under it: that key's indent, line */
  char             scalar[104] = "";

  keys.nseen = keys.nmaps = 0, keys.options_only = options_only;
  if (suspect) suspect->line = suspect->key_line = 0, suspect->text[0] = 0;
  while (!bad) { /* whole lines, of any length */
    char   *c, *v, key[128], full[128] = "", anchor[64];
    int     ind;
    ssize_t got = SceneGetLine(&line, &cap, fp);
    lineno++;
    if (got == SCENE_LINE_NOMEM) {
      snprintf(msg, len, "line %d does not fit in memory", lineno);
      bad = lineno;
      break;
    }
    if (got < 0) {
      for (; depth && !bad; depth--) /* the keys still open at the end: an empty one is a key given */
        if (!kids[depth - 1]) bad = SceneLevelKey(&keys, parent, depth, at[depth - 1], "", msg, len);
      break;
    }
    if (SkipBOM(line, lineno) != line) memmove(line, line + 3, strlen(line + 3) + 1); /* indents count after it */
    c = line;
    line[strcspn(line, "\r\n")] = 0;
    while (*c == ' ' || *c == '\t') c++;
    if (!*c || *c == '#') continue;
    if (*c == '{') {
      snprintf(msg, len, "line %d: a flow map at the start of a line: write its keys as lines 'key: value'", lineno);
      bad = lineno;
      break;
    }
    if (*c == '?' && (!c[1] || c[1] == ' ' || c[1] == '\t')) { /* the key check would not see it */
      snprintf(msg, len, "line %d: an explicit key ('? key' and ': value' on the next line): write it as 'key: value'",
               lineno);
      bad = lineno;
      break;
    }
    if ((*c == '"' || *c == '\'') && strchr(c + 1, *c)) { /* a quoted key ("load\x5fsteps") the check reads raw */
      const char *end = strchr(c + 1, *c), *after = end + 1;
      while (*after == ' ' || *after == '\t') after++;
      if (*after == ':' && memchr(c + 1, '\\', (size_t) (end - c - 1))) {
        snprintf(msg, len, "line %d: an escape in a quoted key (%.60s): write the key plain", lineno, c);
        bad = lineno;
        break;
      }
    }
    ind = (int) (c - line);
    if (scalar_ind >= 0 && ind <= scalar_ind) scalar_ind = -1; /* the value under a key has ended */
    if (scalar_ind >= 0 && suspect && !suspect->line && *c != '-' && *c != '[' && SceneKey(c, key, sizeof key)) {
      suspect->line = scalar_at, suspect->key_line = lineno; /* a key line among the lines of a value */
      memcpy(suspect->text, scalar, sizeof scalar);
    }
    for (; depth && indent[depth - 1] >= ind && !bad; depth--) /* a key closed with nothing under it was given empty */
      if (!kids[depth - 1]) bad = SceneLevelKey(&keys, parent, depth, at[depth - 1], "", msg, len);
    if (bad) break;
    if (*c == '-' || *c == '[' || !(v = SceneKey(c, key, sizeof key))) { /* no key (or FindMalformedLine's case) */
      if (depth && !kids[depth - 1]) { /* under a key with no value on its line: that key's value, not a map */
        if (anchored[depth - 1]) keys.nmaps--; /* its anchor, the last taken, names that value: an alias of it is one */
        if (!(bad = SceneHidden(&keys, parent[depth - 1], c, lineno, msg, len)))
          bad = SceneLevelKey(&keys, parent, depth, at[depth - 1], c, msg, len);
        depth--;
        scalar_ind = indent[depth], scalar_at = lineno;
        snprintf(scalar, sizeof scalar, "%.100s", c);
      }
      continue;
    }
    if (depth) kids[depth - 1]++;
    for (; *v == ' ' || *v == '\t'; v++) {}
    v = SceneValue(v, anchor, sizeof anchor);
    for (int d = 0; d < depth; d++) snprintf(full + strlen(full), sizeof full - strlen(full), "%.100s_", parent[d]);
    snprintf(full + strlen(full), sizeof full - strlen(full), "%.100s", key);
    if ((bad = SceneHidden(&keys, key, v, lineno, msg, len))) break;
    const int added = (!*v || *v == '#' || *v == '{') && anchor[0] && keys.nmaps < SCENE_ANCHORS_MAX;
    if (added) snprintf(keys.maps[keys.nmaps++], sizeof keys.maps[0], "%s", anchor);
    if (!*v || *v == '#') { /* a map: its keys follow, indented */
      if (depth < 8) {
        snprintf(parent[depth], sizeof parent[depth], "%.100s", key);
        kids[depth] = 0, at[depth] = lineno, anchored[depth] = added, indent[depth++] = ind;
      }
    } else if (*v == '{') /* a flow map on this line: each of its keys */
      bad = SceneFlowMap(&keys, full, v, lineno, msg, len);
    else
      bad = SceneKeyOnce(&keys, full, v, lineno, msg, len);
  }
  free(line);
  return bad;
}

static int FindBadKey(const char *file, char *msg, size_t len, Suspect *suspect)
{
  FILE *fp = fopen(file, "r");
  int   bad;
  if (!fp) return 0;
  bad = FindBadKeyIn(fp, 0, msg, len, suspect);
  fclose(fp);
  return bad;
}

/* PETSC_OPTIONS and PETSC_OPTIONS_YAML as rank 0 has them (as PETSc reads them: other ranks may not see the launcher's
   environment), after the scene file, so that they win over it as over the defaults */
static PetscErrorCode InsertEnvOptions(MPI_Comm comm)
{
  static const char *const vars[] = {"PETSC_OPTIONS", "PETSC_OPTIONS_YAML"}; /* PETSc's order */
  PetscMPIInt              rank;

  PetscFunctionBeginUser;
  PetscCall(CommRank(comm, &rank));
  for (int q = 0; q < 2; q++) {
    const char *env = NULL;
    char       *text;
    PetscInt    len = 0;
    if (!rank && (env = getenv(vars[q]))) len = (PetscInt) strlen(env);
    PetscCall(BroadcastFromRoot(comm, &len, 1, MPIU_INT));
    if (!len) continue;
    PetscCall(PetscMalloc1(len + 1, &text));
    if (!rank) PetscCall(PetscArraycpy(text, env, len));
    text[len] = 0;
    PetscCall(BroadcastFromRoot(comm, text, len, MPI_CHAR));
    if (q == 0) PetscCall(PetscOptionsInsertString(NULL, text));
    else PetscCall(PetscOptionsInsertStringYAML(NULL, text)); /* checked before PetscInitialize read it (main.c) */
    PetscCall(PetscFree(text));
  }
  PetscFunctionReturn(0);
}

/* the scene file's text, as rank 0 reads it, on every rank */
static PetscErrorCode ReadSceneText(MPI_Comm comm, const char *file, char **text)
{
  PetscInt    len = 0;
  PetscMPIInt rank;
  char       *buf = NULL;

  PetscFunctionBeginUser;
  PetscCall(CommRank(comm, &rank));
  if (!rank) { /* to its end, whatever size the file reports (a file of /proc reports 0) */
    FILE  *fp  = fopen(file, "r");
    size_t cap = 0, n = 0, got = 1;
    len        = fp ? 0 : -1;
    while (fp && got) {
      if (n == cap) {
        char *b = cap < (size_t) PETSC_MAX_INT / 2 ? realloc(buf, cap = 2 * cap + 65536) : NULL;
        if (!b) {
          len = -2;
          break;
        }
        buf = b;
      }
      got = fread(buf + n, 1, cap - n, fp);
      n += got;
    }
    if (fp && ferror(fp)) len = -1;
    if (fp) fclose(fp);
    if (len == 0) len = (PetscInt) n;
  }
  PetscCall(BroadcastFromRoot(comm, &len, 1, MPIU_INT));
  if (len < 0) free(buf);
  PetscCheck(len != -2, comm, PETSC_ERR_MEM, "-scene %s: the file does not fit in memory", file);
  PetscCheck(len >= 0, comm, PETSC_ERR_FILE_OPEN, "-scene %s: cannot read the file", file);
  {
    PetscErrorCode ierr = PetscMalloc1(len + 1, text);
    if (ierr) free(buf);
    PetscCall(ierr);
  }
  if (!rank) PetscCall(PetscMemcpy(*text, buf, (size_t) len));
  free(buf);
  PetscCall(BroadcastFromRoot(comm, *text, len, MPI_CHAR));
  (*text)[len] = 0;
  { /* a NUL byte would end the text there for the YAML parser: the rest of the file would be left unread */
    const char *nul = memchr(*text, 0, (size_t) len);
    int         lineno = 1;
    for (const char *c = *text; nul && c < nul; c++) lineno += *c == '\n';
    if (nul) PetscCall(PetscFree(*text));
    PetscCheck(!nul, comm, PETSC_ERR_FILE_UNEXPECTED,
               "-scene %s: line %d holds a NUL byte (not a text file?): the options after it would be left unread", file,
               lineno);
  }
  PetscFunctionReturn(0);
}

/* A word on the command line where an option name belongs (a scene file without -scene, or
   load_steps=3) is skipped by PETSc, and the run would go on without it: refuse it. The walk is
   PETSc's own: a name (PetscOptionsValidKey: -x, not -5) takes the next word as its value unless
   that word is a name itself; -prefix_pop takes none. */
static PetscErrorCode CheckBareWords(MPI_Comm comm, int argc, char **argv)
{
  PetscFunctionBeginUser;
  for (int k = 1; k < argc;) {
    PetscBool   key, next = PETSC_TRUE;
    const char *w   = argv[k];
    const char *dot = strrchr(w, '.'), *eq = strchr(w, '=');
    PetscCall(PetscOptionsValidKey(w, &key));
    if (!key) {
      const int yaml = dot && (!strcasecmp(dot, ".yaml") || !strcasecmp(dot, ".yml"));
      PetscCheck(!eq || eq == w, comm, PETSC_ERR_USER_INPUT,
                 "'%s' on the command line is not an option: options are given as -name value (-%.*s %s)", w,
                 (int) (eq - w), w, eq + 1);
      PetscCheck(!yaml, comm, PETSC_ERR_USER_INPUT,
                 "'%s' on the command line is not an option: a scene file is given as -scene %s", w, w);
      SETERRQ(comm, PETSC_ERR_USER_INPUT,
              "'%s' on the command line is not an option, nor the value of one (%s%s): options are given as -name value",
              w, k > 1 ? "it follows " : "it is the first word", k > 1 ? argv[k - 1] : "");
    }
    if (k + 1 < argc && strcasecmp(w, "-prefix_pop")) PetscCall(PetscOptionsValidKey(argv[k + 1], &next));
    k += next ? 1 : 2;
  }
  PetscFunctionReturn(0);
}

/* -scene FILE: insert the YAML option file, then PETSC_OPTIONS and the command line again so that they win
   (PETSc's order: option files, the environment, the command line) */
PetscErrorCode SceneInsertFile(MPI_Comm comm, int argc, char **argv)
{
  char           file[PETSC_MAX_PATH_LEN], *text;
  PetscBool      set;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  { /* given twice on the command line, one of these would replace the other as a whole, not add to it */
#define LIST_ONCE "would replace the others, not add to them); give every item in one value, its numbers joined by commas"
    static const struct {
      const char *name, *why;
    } once[] = {
        {"-scene", "would be the only one read); give one scene file and the options that change it"},
        {"-clamp_line_mm", LIST_ONCE},
        {"-grip_line_mm", LIST_ONCE},
        {"-grip_path_mm", LIST_ONCE},
    };
#undef LIST_ONCE
    for (size_t q = 0; q < sizeof once / sizeof once[0]; q++) {
      int given = 0, last = 0;
      for (int k = 1; k < argc; k++)
        if (!strcasecmp(argv[k], once[q].name)) given++, last = k;
      PetscCheck(given <= 1, comm, PETSC_ERR_USER_INPUT, "%s given %d times on the command line (the last, %s, %s",
                 once[q].name, given, last + 1 < argc ? argv[last + 1] : "", once[q].why);
    }
  }
  PetscCall(CheckBareWords(comm, argc, argv));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", file, sizeof file, &set));
  if (!set) PetscFunctionReturn(0);
  PetscCheck(file[0], comm, PETSC_ERR_USER_INPUT, "-scene needs a file name");
  PetscCall(SceneCheckReadable(comm, "-scene", file));
  PetscCall(CheckSceneHasOptions(comm, file));
  char    found[512] = ""; /* the key check's finding */
  Suspect suspect    = {0, 0, ""};
  {
    PetscMPIInt rank;
    PetscCall(CommRank(comm, &rank));
    if (!rank) (void) FindBadKey(file, found, sizeof found, &suspect); /* rank 0 reads, every rank refuses alike */
    PetscCall(BroadcastFromRoot(comm, found, (PetscInt) sizeof found, MPI_CHAR));
    PetscCall(BroadcastFromRoot(comm, &suspect, (PetscInt) sizeof suspect, MPI_CHAR));
    /* in a file whose lines the check may have misread (a suspect line), libyaml's verdict first */
    PetscCheck(!found[0] || suspect.line, comm, PETSC_ERR_USER_INPUT, "-scene %s: %s", file, found);
  }
  PetscCall(ReadSceneText(comm, file, &text));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = PetscOptionsInsertStringYAML(NULL, text); /* the text as read: PetscOptionsInsertFileYAML would open the
                                                      file by another name ('\\' made '/', ${VAR} expanded) */
  PetscCall(PetscPopErrorHandler());
  if (ierr) { /* said where: a line that cannot be "key: value", else libyaml's problem and place */
    const char *msg;
    char       *specific = NULL;
    char        bad[256], where[512] = "";
    const char *why    = NULL;
    int         lineno = 0, at = 0;
    if (suspect.line && YamlProblem(text, where, sizeof where) && sscanf(where, "line %d", &at) == 1 &&
        at == suspect.key_line) { /* libyaml refuses the first key line after a value: that value's line lost its colon */
      lineno = suspect.line, why = "expected 'key: value'";
      PetscCall(PetscStrncpy(bad, suspect.text, sizeof bad));
    }
    where[0] = 0;
    if (!lineno) lineno = FindMalformedLine(file, bad, sizeof bad, &why);
    if (!lineno) (void) YamlProblem(text, where, sizeof where); /* where stays "" if libyaml finds nothing */
    PetscCall(PetscFree(text));
    PetscCall(PetscErrorMessage(ierr, &msg, &specific));
    if (specific && specific[0]) msg = specific;
    PetscCheck(!lineno, comm, PETSC_ERR_FILE_UNEXPECTED, "-scene %s: not a valid YAML option file: %s (line %d, '%s': %s)",
               file, msg, lineno, bad, why);
    PetscCheck(!where[0], comm, PETSC_ERR_FILE_UNEXPECTED, "-scene %s: not a valid YAML option file: %s", file, where);
    SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "-scene %s: not a valid YAML option file: %s", file, msg);
  }
  PetscCall(PetscFree(text));
  PetscCheck(!found[0], comm, PETSC_ERR_USER_INPUT, "-scene %s: %s", file, found); /* YAML as libyaml reads it */
  PetscCall(InsertEnvOptions(comm));
  PetscCall(PetscOptionsInsertArgs(NULL, argc - 1, argv + 1));
  PetscFunctionReturn(0);
}

/* PETSc's options read by PetscInitialize, before the scene file is inserted: from a scene, they are left unused */
static PetscBool StartupOption(const char *name)
{
  static const char *const startup[] = {"log_view",         "log_all",           "log_trace",       "log_exclude",
                                        "log_sync",         "info",              "info_exclude",    "history",
                                        "malloc_debug",     "malloc_dump",       "malloc_view",     "malloc_test",
                                        "memory_view",      "options_file",      "options_file_yaml", "options_monitor",
                                        "on_error_abort",   "on_error_attach_debugger", "start_in_debugger",
                                        "stop_for_debugger", "no_signal_handler", "skip_petscrc",   "objects_dump",
                                        "malloc_info"};
  for (size_t q = 0; q < sizeof startup / sizeof startup[0]; q++)
    if (!strcasecmp(name, startup[q])) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* A misspelt option would otherwise be ignored silently: refuse it. */
PetscErrorCode SceneCheckUnused(MPI_Comm comm, PetscBool solver_options_later)
{
  PetscInt n;
  char   **names, **values;

  PetscFunctionBeginUser;
  { /* PETSc's own, read at PetscFinalize: -options_left; refused: -fp_trap (the kernels are built with
       -fno-trapping-math, so both arms of a select run, and a discarded 1/0 would trap; a value
       that is not finite stops the run by its own checks) */
    PetscBool set, trap = PETSC_FALSE;
    PetscCall(PetscOptionsHasName(NULL, NULL, "-options_left", &set));
    PetscCall(PetscOptionsHasName(NULL, NULL, "-options_view", &set));
    PetscCall(PetscOptionsHasName(NULL, NULL, "-get_total_flops", &set));
    PetscCall(PetscOptionsGetBool(NULL, NULL, "-fp_trap", &trap, NULL));
    PetscCheck(!trap, comm, PETSC_ERR_USER_INPUT,
               "-fp_trap: the force kernels evaluate both arms of their selects, so a trap would fire on a value "
               "they discard; a value that is not finite stops the run with its own message");
  }
  { /* -dm_mat_type: DMSetFromOptions takes it (any value), and no matrix of the fabric's is made from it */
    char      type[256] = "";
    PetscBool set;
    PetscCall(PetscOptionsGetString(NULL, NULL, "-dm_mat_type", type, sizeof type, &set));
    PetscCheck(!set, comm, PETSC_ERR_USER_INPUT,
               "-dm_mat_type %s: not read: the fabric makes its matrices itself (the quasi-static tangent's storage: "
               "-static_tangent stencil or aij)",
               type);
  }
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  for (PetscInt q = 0; q < n; q++) {
    char name[256];
    PetscBool solver = SceneSolverOption(names[q]);
    if (solver_options_later && solver) continue;
    solver = solver || !strncmp(names[q], "static_", 7) ? PETSC_TRUE : PETSC_FALSE;
    PetscCall(PetscStrncpy(name, names[q], sizeof name));
    PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
    PetscCheck(solver_options_later || !solver, comm, PETSC_ERR_USER_INPUT,
               "-%s: an option of the quasi-static solver, read with -solver static only (this run is -solver explicit)",
               name);
    /* an option file named by a YAML key (the scene, a YAML option file, PETSC_OPTIONS_YAML) is never read */
    PetscCheck(strcasecmp(name, "options_file") && strcasecmp(name, "options_file_yaml"), comm, PETSC_ERR_USER_INPUT,
               "-%s in YAML options (the scene, a YAML option file or PETSC_OPTIONS_YAML): PETSc does not read a file "
               "named by this key; give it on the command line, in PETSC_OPTIONS or in a plain option file",
               name);
    PetscCheck(!StartupOption(name), comm, PETSC_ERR_USER_INPUT,
               "-%s in the scene file: PETSc reads it as it starts, before the scene; give it on the command line or in "
               "PETSC_OPTIONS",
               name);
    SETERRQ(comm, PETSC_ERR_USER_INPUT, "unknown option -%s (run with -help for the list)", name);
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneWarnUnused(MPI_Comm comm, const char *when)
{
  PetscInt n;
  char   **names, **values;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  for (PetscInt q = 0; q < n; q++) {
    char      name[256];
    PetscBool set;
    PetscCall(PetscPrintf(comm, "fabric: warning: option -%s was not used%s%s (check its spelling: -help lists them)\n",
                          names[q], when[0] ? " " : "", when));
    PetscCall(PetscSNPrintf(name, sizeof name, "-%s", names[q]));
    PetscCall(PetscOptionsHasName(NULL, NULL, name, &set)); /* marks it used: warned once */
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
  PetscFunctionReturn(0);
}
