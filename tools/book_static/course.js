/* The course book's own script (tools/book.py): see the comments below. */
